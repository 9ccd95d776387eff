// C3D writer: Intel processor, float storage, points only (see WriteC3d in recording_io.h).
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "mocap/c3d_format.h"
#include "mocap/file_util.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::mocap {

namespace {

using internal::Fail;

constexpr std::size_t kMaxPerParameter = 255;  // a dimension is one byte

void AppendInt16(std::string& out, std::int64_t value) {
  const auto bits = static_cast<std::uint16_t>(value);
  out.push_back(static_cast<char>(bits & 0xffu));
  out.push_back(static_cast<char>(bits >> 8));
}

void AppendFloat(std::string& out, float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
}

// Writes the items of a parameter section (Intel byte order); each item's offset points to the
// next, the last one's is 0.
class ParameterWriter {
 public:
  explicit ParameterWriter(const std::filesystem::path& path) : path_(path) {}

  void Group(int id, std::string_view name) {
    Begin(-id, name);
    out_.push_back('\0');  // no description
  }
  void Int16s(int group, std::string_view name, const std::vector<std::int64_t>& values) {
    Begin(group, name);
    Shape(2, {static_cast<int>(values.size())});
    for (std::int64_t v : values) AppendInt16(out_, v);
    out_.push_back('\0');
  }
  void Float(int group, std::string_view name, float value) {
    Begin(group, name);
    Shape(4, {});
    AppendFloat(out_, value);
    out_.push_back('\0');
  }
  // Strings padded with spaces to a common length: dimensions [length, count], or [length] for
  // a single string.
  void Strings(int group, std::string_view name, const std::vector<std::string>& strings,
               bool single = false) {
    std::size_t length = 1;
    for (const auto& s : strings) length = std::max(length, s.size());
    if (length > 255) {
      Fail(path_, fmt::format("parameter {}", name), "a string longer than 255 characters");
    }
    Begin(group, name);
    if (single) {
      Shape(-1, {static_cast<int>(length)});
    } else {
      Shape(-1, {static_cast<int>(length), static_cast<int>(strings.size())});
    }
    for (const auto& s : strings) out_ += s + std::string(length - s.size(), ' ');
    out_.push_back('\0');
  }
  // The section (after its 4-byte header), padded to whole blocks together with it.
  std::string Finish() {
    if (last_offset_at_ != std::string::npos) out_[last_offset_at_] = out_[last_offset_at_ + 1] = 0;
    std::string section = out_;
    const std::size_t total = 4 + section.size();
    section.resize(
        section.size() + (c3d::kBlockBytes - total % c3d::kBlockBytes) % c3d::kBlockBytes, '\0');
    return section;
  }

 private:
  void Begin(int id, std::string_view name) {
    Close();
    out_.push_back(static_cast<char>(name.size()));
    out_.push_back(static_cast<char>(static_cast<std::int8_t>(id)));
    out_ += name;
    last_offset_at_ = out_.size();
    AppendInt16(out_, 0);  // patched by Close()
  }
  void Shape(int type, std::initializer_list<int> dimensions) {
    out_.push_back(static_cast<char>(static_cast<std::int8_t>(type)));
    out_.push_back(static_cast<char>(dimensions.size()));
    for (int d : dimensions) out_.push_back(static_cast<char>(static_cast<std::uint8_t>(d)));
  }
  void Close() {
    if (last_offset_at_ == std::string::npos) return;
    const std::size_t offset = out_.size() - last_offset_at_;
    out_[last_offset_at_] = static_cast<char>(offset & 0xffu);
    out_[last_offset_at_ + 1] = static_cast<char>(offset >> 8);
  }

  const std::filesystem::path& path_;
  std::string out_;
  std::size_t last_offset_at_ = std::string::npos;
};

// LABELS, LABELS2, LABELS3, … with at most 255 strings each.
void WriteNameChunks(ParameterWriter& w, int group, std::string_view name,
                     const std::vector<std::string>& names) {
  for (std::size_t begin = 0, k = 1; begin < names.size() || k == 1;
       begin += kMaxPerParameter, ++k) {
    const std::size_t end = std::min(names.size(), begin + kMaxPerParameter);
    const std::vector<std::string> chunk(names.begin() + static_cast<std::ptrdiff_t>(begin),
                                         names.begin() + static_cast<std::ptrdiff_t>(end));
    w.Strings(group, k == 1 ? std::string(name) : fmt::format("{}{}", name, k), chunk);
  }
}

// POINT:ANGLES, FORCES, … for the types the recording holds, and the units it states.
void WritePointTypes(ParameterWriter& w, const Recording& r) {
  for (const auto& group : c3d::kPointTypeParameters) {
    std::vector<std::string> names;
    for (int m = 0; m < r.markers(); ++m) {
      if (r.type(m) == group.type) names.push_back(r.labels()[static_cast<std::size_t>(m)]);
    }
    if (!names.empty()) WriteNameChunks(w, 1, group.labels, names);
    const std::string& units = r.type_units(group.type);
    if (!units.empty()) w.Strings(1, group.units, {units}, true);
  }
}

std::string ParameterSectionBytes(const Recording& r, const std::filesystem::path& path,
                                  std::int64_t data_start) {
  const std::int64_t last = r.first_frame() + r.frames() - 1;
  ParameterWriter w(path);
  w.Group(1, "POINT");
  w.Int16s(1, "USED", {r.markers()});
  w.Float(1, "SCALE", -1.0f);
  w.Float(1, "RATE", static_cast<float>(r.rate()));
  w.Int16s(1, "DATA_START", {data_start});
  // Beyond 65535 frames the count saturates (0xFFFF, as ezc3d and Vicon write it; readers that
  // expect an integer reject a float) and the TRIAL fields hold the true range.
  w.Int16s(1, "FRAMES", {std::min<std::int64_t>(r.frames(), 65535)});
  w.Strings(1, "UNITS", {r.units()}, true);
  WriteNameChunks(w, 1, "LABELS", r.labels());
  std::vector<std::string> descriptions = r.descriptions();
  descriptions.resize(static_cast<std::size_t>(r.markers()));
  WriteNameChunks(w, 1, "DESCRIPTIONS", descriptions);
  WritePointTypes(w, r);
  w.Group(2, "ANALOG");
  w.Int16s(2, "USED", {0});
  w.Float(2, "RATE", static_cast<float>(r.rate()));
  w.Group(3, "TRIAL");
  w.Int16s(3, "ACTUAL_START_FIELD", {r.first_frame() & 0xffff, r.first_frame() >> 16});
  w.Int16s(3, "ACTUAL_END_FIELD", {last & 0xffff, last >> 16});
  w.Float(3, "CAMERA_RATE", static_cast<float>(r.rate()));
  return w.Finish();
}

std::string HeaderBytes(const Recording& r, std::int64_t data_start) {
  std::string h;
  h.push_back(2);  // the parameter section starts at block 2
  h.push_back(0x50);
  AppendInt16(h, r.markers());
  AppendInt16(h, 0);  // analog values per frame
  AppendInt16(h, std::min<std::int64_t>(r.first_frame(), 65535));
  AppendInt16(h, std::min<std::int64_t>(r.first_frame() + r.frames() - 1, 65535));
  AppendInt16(h, 0);  // maximum interpolation gap
  AppendFloat(h, -1.0f);
  AppendInt16(h, data_start);
  AppendInt16(h, 0);  // analog samples per frame
  AppendFloat(h, static_cast<float>(r.rate()));
  h.resize(c3d::kBlockBytes, '\0');
  return h;
}

}  // namespace

void WriteC3d(const Recording& r, const std::filesystem::path& path) {
  if (r.markers() > 65535)
    Fail(path, "POINT:USED", fmt::format("{} markers exceed 65535", r.markers()));
  if (r.first_frame() < 0 || r.first_frame() + r.frames() - 1 > 2147483647) {
    Fail(path, "TRIAL:ACTUAL_START_FIELD",
         fmt::format("frames {} … {} are outside 0 … 2^31 − 1", r.first_frame(),
                     r.first_frame() + r.frames() - 1));
  }
  const std::size_t section_blocks =
      (4 + ParameterSectionBytes(r, path, 0).size()) / c3d::kBlockBytes;
  if (section_blocks > 255) {
    Fail(path, "parameter section",
         fmt::format("{} blocks exceed 255 (too many labels)", section_blocks));
  }
  const auto data_start = static_cast<std::int64_t>(2 + section_blocks);
  std::string out = HeaderBytes(r, data_start);
  out.push_back(1);  // parameter section header: first-block byte, key 0x50, blocks, processor
  out.push_back(0x50);
  out.push_back(static_cast<char>(section_blocks));
  out.push_back(static_cast<char>(c3d::Processor::kIntel));
  out += ParameterSectionBytes(r, path, data_start);
  out.reserve(out.size() + 16 * static_cast<std::size_t>(r.frames() * r.markers()));
  for (std::int64_t f = 0; f < r.frames(); ++f) {
    for (int m = 0; m < r.markers(); ++m) {
      const bool observed = r.observed(f, m);
      for (int c = 0; c < 3; ++c)
        AppendFloat(out, observed ? static_cast<float>(r.point(f, m)[c]) : 0.0f);
      AppendFloat(out, observed ? 0.0f : -1.0f);
    }
  }
  internal::WriteFileAtomically(path, out);
}

}  // namespace moreau::mocap
