// VTU series with a PVD index (layout in include/moreau/io/trajectory.h, docs/io.md).
#include <fmt/format.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/io_util.h"
#include "moreau/common/error.h"
#include "moreau/io/trajectory.h"

namespace moreau::io {
namespace {

constexpr std::uint8_t kVtkVertex = 1;

// The frame's extra arrays (PointArray) as point data.
void AppendPointArrays(const ParticleFrame& frame, std::string& out) {
  const auto n = static_cast<std::size_t>(frame.count);
  for (const PointArray& a : frame.arrays) {
    const std::string name = internal::XmlEscape(a.name);
    const std::size_t values = n * static_cast<std::size_t>(a.components);
    if (a.type == PointArray::Type::kInt64) {
      internal::AppendDataArray("Int64", name.c_str(), a.components,
                                static_cast<const std::int64_t*>(a.data), values, out);
    } else {
      internal::AppendDataArray("Float64", name.c_str(), a.components,
                                static_cast<const double*>(a.data), values, out);
    }
  }
}

class VtuSeriesWriter final : public TrajectoryWriter {
 public:
  VtuSeriesWriter(std::filesystem::path dir, std::string prefix, std::vector<StringList> lists);
  ~VtuSeriesWriter() override {
    try {
      Close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the destructor must not throw
    }
  }
  VtuSeriesWriter(const VtuSeriesWriter&) = delete;
  VtuSeriesWriter& operator=(const VtuSeriesWriter&) = delete;

  void Write(const ParticleFrame& frame) override;
  void Close() override;

 private:
  std::filesystem::path dir_;
  std::string prefix_;
  std::filesystem::path pvd_path_;
  std::vector<StringList> lists_;
  std::vector<internal::ArraySpec> specs_;             // the extra arrays, fixed by the first frame
  std::vector<std::pair<double, std::string>> files_;  // (time, file name) per frame
  bool closed_ = false;
  // Workspace reused between frames.
  std::vector<double> points_;
  std::vector<std::int64_t> connectivity_, offsets_;
  std::vector<std::uint8_t> types_;
  std::string text_;
};

VtuSeriesWriter::VtuSeriesWriter(std::filesystem::path dir, std::string prefix,
                                 std::vector<StringList> lists)
    : dir_(std::move(dir)), prefix_(std::move(prefix)), lists_(std::move(lists)) {
  constexpr std::string_view kTaken[] = {"TimeValue", "step"};
  internal::ValidateLists(lists_, kTaken, dir_ / (prefix_ + ".pvd"));
  pvd_path_ = internal::StartSeriesIndex(dir_, prefix_, "VTU");
}

void VtuSeriesWriter::Write(const ParticleFrame& frame) {
  if (closed_) throw std::logic_error(fmt::format("{}: Write after Close", pvd_path_.string()));
  const std::string name = fmt::format("{}_{:06d}.vtu", prefix_, files_.size());
  const std::filesystem::path path = dir_ / name;
  internal::ValidateFrame(frame, path);
  if (!files_.empty() && frame.time < files_.back().first) {
    throw InputError(fmt::format("{}: frame at step {} has time {} before the previous frame's {}",
                                 path.string(), frame.step, frame.time, files_.back().first));
  }
  if (files_.empty()) specs_ = internal::SpecsOf(frame.arrays);
  internal::CheckSameArrays(specs_, frame, path);
  const auto n = static_cast<std::size_t>(frame.count);
  const auto k = static_cast<std::size_t>(frame.dimension);
  points_.assign(3 * n, 0.0);
  connectivity_.resize(n);
  offsets_.resize(n);
  types_.assign(n, kVtkVertex);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t a = 0; a < k; ++a) points_[3 * i + a] = frame.positions[k * i + a];
    connectivity_[i] = static_cast<std::int64_t>(i);
    offsets_[i] = static_cast<std::int64_t>(i + 1);
  }

  std::string& out = text_;
  out.clear();
  out += "<?xml version=\"1.0\"?>\n";
  out += fmt::format(
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" "
      "header_type=\"UInt64\">\n",
      internal::kByteOrder);
  out += "  <UnstructuredGrid>\n";
  out += "    <FieldData>\n";
  internal::AppendTimeAndStep(frame.time, frame.step, out);
  for (const StringList& list : lists_) internal::AppendStringArray(list, out);
  out += "    </FieldData>\n";
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
  out += "      <PointData Scalars=\"radius\">\n";
  internal::AppendDataArray("Float64", "radius", 1, frame.radii, n, out);
  internal::AppendDataArray("Int64", "id", 1, frame.ids, n, out);
  AppendPointArrays(frame, out);
  out += "      </PointData>\n";
  out += "      <Points>\n";
  internal::AppendDataArray("Float64", "Points", 3, points_.data(), 3 * n, out);
  out += "      </Points>\n";
  out += "      <Cells>\n";
  internal::AppendDataArray("Int64", "connectivity", 1, connectivity_.data(), n, out);
  internal::AppendDataArray("Int64", "offsets", 1, offsets_.data(), n, out);
  internal::AppendDataArray("UInt8", "types", 1, types_.data(), n, out);
  out += "      </Cells>\n";
  out += "    </Piece>\n";
  out += "  </UnstructuredGrid>\n";
  out += "</VTKFile>\n";
  internal::WriteWholeFile(path, out);
  files_.emplace_back(frame.time, name);
}

void VtuSeriesWriter::Close() {
  if (closed_) return;
  closed_ = true;
  std::string().swap(text_);
  internal::WriteWholeFile(pvd_path_, internal::PvdText(files_));
}

}  // namespace

std::unique_ptr<TrajectoryWriter> MakeVtuSeriesWriter(const std::filesystem::path& dir,
                                                      const std::string& prefix,
                                                      const std::vector<StringList>& lists) {
  return std::make_unique<VtuSeriesWriter>(dir, prefix, lists);
}

}  // namespace moreau::io
