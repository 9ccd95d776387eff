// Grid writers: HDF5 read back bit for bit through the HDF5 C API with its views and attributes,
// the XDMF sidecar's mesh, the VTI files decoded from base64 and the PVD index, the same bytes for
// the same frames, bad grids and frames, a full disk. FieldSample.* also leaves a 2D and a 3D
// sample (fields and particles at the same times) for the client suite and the figure script.
#include "moreau/io/grid_writer.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/io_test_util.h"
#include "moreau/common/error.h"
#include "moreau/io/trajectory.h"

namespace moreau::io {
namespace {

namespace fs = std::filesystem;
using namespace test_util;  // NOLINT(google-build-using-namespace)

// The frames of a run on one grid, with their own storage: field "c" = x + 2y + 3z + t at each
// voxel's centre (z = 0 in 2D), and field "noise", seeded random values with awkward doubles.
struct GridFrames {
  GridSpec grid;
  std::vector<std::int64_t> steps;
  std::vector<double> times;
  std::vector<std::vector<double>> c, noise;
  std::vector<std::vector<GridArray>> arrays;  // views of c and noise per frame

  std::size_t size() const { return times.size(); }
  GridFrame frame(std::size_t f) const { return {steps[f], times[f], arrays[f]}; }
};

// The centre of voxel `v` (index order i + n_x (j + n_y l)); z = 0 in 2D.
std::array<double, 3> Centre(const GridSpec& g, std::int64_t v) {
  const std::int64_t nx = g.cells[0], ny = g.cells[1];
  const std::int64_t index[3] = {v % nx, (v / nx) % ny, v / (nx * ny)};
  std::array<double, 3> x{0.0, 0.0, 0.0};
  for (int a = 0; a < g.dimension; ++a) {
    x[a] = g.origin[a] + g.spacing * (static_cast<double>(index[a]) + 0.5);
  }
  return x;
}

double Analytic(const std::array<double, 3>& x, double t) { return x[0] + 2 * x[1] + 3 * x[2] + t; }

GridFrames MakeFrames(const GridSpec& grid, const std::vector<double>& times, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  GridFrames s;
  s.grid = grid;
  s.times = times;
  const std::int64_t n = grid.voxel_count();
  for (std::size_t f = 0; f < times.size(); ++f) {
    s.steps.push_back(10 * static_cast<std::int64_t>(f) + 1);
    std::vector<double> c(static_cast<std::size_t>(n)), noise(c.size());
    for (std::int64_t v = 0; v < n; ++v) c[v] = Analytic(Centre(grid, v), times[f]);
    for (double& x : noise) x = u(rng);
    noise[0] = -0.0;
    if (noise.size() >= 3) {
      noise[1] = 4.9e-324;
      noise[2] = -1.7976931348623157e308;
    }
    s.c.push_back(std::move(c));
    s.noise.push_back(std::move(noise));
  }
  for (std::size_t f = 0; f < times.size(); ++f) {
    s.arrays.push_back({{"c", s.c[f]}, {"noise", s.noise[f]}});
  }
  return s;
}

GridSpec Grid2D() { return {2, {-1.0, 0.5, 7.0}, 0.25, {8, 6, 1}}; }
GridSpec Grid3D() { return {3, {-1.0, 0.5, 2.0}, 0.5, {4, 3, 5}}; }
const std::vector<double> kTimes{0.0, 0.5, 1.25};

void WriteGridFrames(GridWriter& writer, const GridFrames& frames) {
  for (std::size_t f = 0; f < frames.size(); ++f) writer.Write(frames.frame(f));
  writer.Close();
}

// The frames' arrays one after the other (F × voxels), as /fields/NAME holds them.
std::vector<double> Stacked(const std::vector<std::vector<double>>& frames) {
  std::vector<double> out;
  for (const auto& f : frames) out.insert(out.end(), f.begin(), f.end());
  return out;
}

// --- HDF5 ---------------------------------------------------------------------------------------

void ExpectGridHdf5Matches(const fs::path& path, const GridFrames& expected) {
  H5 file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_GE(file.get(), 0) << path;
  const GridSpec& g = expected.grid;
  const auto frames = static_cast<hsize_t>(expected.size());
  std::vector<hsize_t> shape{static_cast<hsize_t>(g.cells[1]), static_cast<hsize_t>(g.cells[0])};
  if (g.dimension == 3) shape.insert(shape.begin(), static_cast<hsize_t>(g.cells[2]));
  std::vector<hsize_t> dims{frames};
  dims.insert(dims.end(), shape.begin(), shape.end());

  EXPECT_EQ(ReadStringAttribute(file.get(), "format"), "moreau-fields");
  EXPECT_EQ(ReadScalarAttribute<int>(file.get(), "format_version", H5T_NATIVE_INT), 1);
  EXPECT_EQ(ReadScalarAttribute<int>(file.get(), "dimension", H5T_NATIVE_INT), g.dimension);
  EXPECT_EQ(ReadScalarAttribute<double>(file.get(), "spacing", H5T_NATIVE_DOUBLE), g.spacing);
  const auto k = static_cast<std::size_t>(g.dimension);
  std::vector<double> origin(k);
  std::vector<std::int64_t> cells(k);
  H5 origin_attribute(H5Aopen(file.get(), "origin", H5P_DEFAULT), H5Aclose);
  ASSERT_GE(H5Aread(origin_attribute.get(), H5T_NATIVE_DOUBLE, origin.data()), 0);
  H5 cells_attribute(H5Aopen(file.get(), "cells", H5P_DEFAULT), H5Aclose);
  ASSERT_GE(H5Aread(cells_attribute.get(), H5T_NATIVE_INT64, cells.data()), 0);
  for (std::size_t a = 0; a < k; ++a) {
    EXPECT_EQ(origin[a], g.origin[a]);
    EXPECT_EQ(cells[a], g.cells[a]);
  }

  std::vector<double> time;
  std::vector<std::int64_t> step;
  EXPECT_EQ(ReadDataset(file.get(), "/time", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, time).dims,
            std::vector<hsize_t>{frames});
  ReadDataset(file.get(), "/step", H5T_NATIVE_INT64, H5T_STD_I64LE, step);
  EXPECT_TRUE(SameBits(time, expected.times));
  EXPECT_EQ(step, expected.steps);
  for (const char* name : {"c", "noise"}) {
    const auto& want = std::string(name) == "c" ? expected.c : expected.noise;
    std::vector<double> values;
    const DatasetInfo info = ReadDataset(file.get(), ("/fields/" + std::string(name)).c_str(),
                                         H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, values);
    EXPECT_TRUE(info.file_type_ok && info.chunked) << name;
    EXPECT_EQ(info.dims, dims) << name;
    EXPECT_EQ(info.max_dims[0], H5S_UNLIMITED);
    EXPECT_TRUE(SameBits(values, Stacked(want))) << name;
    for (std::size_t f = 0; f < expected.size(); ++f) {
      char view[64];
      std::snprintf(view, sizeof(view), "/xdmf/frame_%06zu/%s", f, name);
      std::vector<double> frame_values;
      EXPECT_EQ(ReadDataset(file.get(), view, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, frame_values).dims,
                (std::vector<hsize_t>{g.dimension == 3 ? shape[0] : 1, shape[shape.size() - 2],
                                      shape.back()}));
      EXPECT_TRUE(SameBits(frame_values, want[f])) << view;
    }
  }
}

// The text between the `n`-th occurrence of `open` and the next `close`.
std::string Between(const std::string& text, const std::string& open, const std::string& close,
                    std::size_t n = 0) {
  std::size_t p = 0;
  for (std::size_t i = 0; i <= n; ++i) {
    p = text.find(open, i == 0 ? 0 : p + 1);
    if (p == std::string::npos) return {};
  }
  const std::size_t start = p + open.size();
  return text.substr(start, text.find(close, start) - start);
}

void ExpectGridXdmfMatches(const fs::path& path, const GridFrames& expected) {
  const std::string xdmf = ReadText(path);
  const GridSpec& g = expected.grid;
  const auto [nx, ny, nz] = g.cells;
  const bool flat = g.dimension == 2;
  EXPECT_EQ(XmlNestingError(xdmf), "");
  EXPECT_EQ(CountOccurrences(xdmf, "GridType=\"Uniform\""), expected.size());
  EXPECT_EQ(CountOccurrences(xdmf, "TopologyType=\"3DCoRectMesh\""), expected.size());
  EXPECT_EQ(CountOccurrences(xdmf, "Center=\"Cell\""), 2 * expected.size());
  // Points per axis, slowest first; one layer of voxels of thickness h centred on z = 0 in 2D.
  const std::string points =
      flat ? "2 " + std::to_string(ny + 1) + " " + std::to_string(nx + 1)
           : std::to_string(nz + 1) + " " + std::to_string(ny + 1) + " " + std::to_string(nx + 1);
  EXPECT_EQ(AttributeValue(xdmf, "Dimensions", xdmf.find("<Topology")), points);
  const std::string origin = Between(xdmf, "Format=\"XML\">", "<", 0);
  const std::string spacing = Between(xdmf, "Format=\"XML\">", "<", 1);
  std::istringstream o(origin), h(spacing);
  double z = 0, y = 0, x = 0, hz = 0, hy = 0, hx = 0;
  o >> z >> y >> x;
  h >> hz >> hy >> hx;
  EXPECT_EQ(x, g.origin[0]);
  EXPECT_EQ(y, g.origin[1]);
  EXPECT_EQ(z, flat ? -0.5 * g.spacing : g.origin[2]);
  EXPECT_TRUE(hx == g.spacing && hy == g.spacing && hz == g.spacing) << spacing;
  const std::string cells =
      std::to_string(flat ? 1 : nz) + " " + std::to_string(ny) + " " + std::to_string(nx);
  for (std::size_t f = 0; f < expected.size(); ++f) {
    EXPECT_EQ(std::stod(Between(xdmf, "<Time Value=\"", "\"", f)), expected.times[f]);
    char item[96];
    std::snprintf(item, sizeof(item), "Format=\"HDF\">%s:/xdmf/frame_%06zu/noise<",
                  path.stem().string().append(".h5").c_str(), f);
    const std::size_t p = xdmf.find(item);
    ASSERT_NE(p, std::string::npos) << item;
    EXPECT_EQ(AttributeValue(xdmf, "Dimensions", xdmf.rfind("<DataItem", p)), cells);
  }
}

void ExpectHdf5RoundTrip(const GridSpec& grid, std::uint64_t seed) {
  TempDir dir;
  const GridFrames frames = MakeFrames(grid, kTimes, seed);
  WriteGridFrames(*MakeHdf5GridWriter(dir.path() / "fields.h5", frames.grid), frames);
  ExpectGridHdf5Matches(dir.path() / "fields.h5", frames);
  ExpectGridXdmfMatches(dir.path() / "fields.xdmf", frames);
}

TEST(Hdf5GridWriter, RoundTripsEveryValueBitForBit2D) { ExpectHdf5RoundTrip(Grid2D(), 3); }
TEST(Hdf5GridWriter, RoundTripsEveryValueBitForBit3D) { ExpectHdf5RoundTrip(Grid3D(), 4); }

TEST(Hdf5GridWriter, FramesOverAMebibyteAreCutIntoChunksAlongZ) {
  TempDir dir;
  const GridFrames frames = MakeFrames({3, {0, 0, 0}, 1.0, {80, 80, 41}}, {0.0, 1.0}, 5);
  WriteGridFrames(*MakeHdf5GridWriter(dir.path() / "big.h5", frames.grid), frames);
  ExpectGridHdf5Matches(dir.path() / "big.h5", frames);
  H5 file(H5Fopen((dir.path() / "big.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  std::vector<double> values;
  const DatasetInfo info =
      ReadDataset(file.get(), "/fields/c", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, values);
  EXPECT_EQ(info.chunk, (std::vector<hsize_t>{1, 20, 80, 80}));  // 20 · 80 · 80 · 8 B ≤ 1 MiB
  const GridFrames small = MakeFrames(Grid2D(), kTimes, 6);
  WriteGridFrames(*MakeHdf5GridWriter(dir.path() / "small.h5", small.grid), small);
  H5 small_file(H5Fopen((dir.path() / "small.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  EXPECT_EQ(
      ReadDataset(small_file.get(), "/fields/c", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, values).chunk,
      (std::vector<hsize_t>{64, 6, 8}));  // whole frames, at most 64 a chunk
}

TEST(Hdf5GridWriter, NoFramesGivesEmptyTimeAxisAndSidecar) {
  TempDir dir;
  MakeHdf5GridWriter(dir.path() / "fields.h5", Grid3D())->Close();
  H5 file(H5Fopen((dir.path() / "fields.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  std::vector<double> time;
  EXPECT_EQ(ReadDataset(file.get(), "/time", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, time).dims,
            std::vector<hsize_t>{0});
  const std::string xdmf = ReadText(dir.path() / "fields.xdmf");
  EXPECT_EQ(XmlNestingError(xdmf), "");
  EXPECT_EQ(CountOccurrences(xdmf, "GridType=\"Uniform\""), 0u);
}

// --- VTI series ---------------------------------------------------------------------------------

void ExpectVtiSeriesMatches(const fs::path& dir, const std::string& prefix,
                            const GridFrames& expected) {
  const std::string pvd = ReadText(dir / (prefix + ".pvd"));
  EXPECT_EQ(XmlNestingError(pvd), "");
  EXPECT_EQ(CountOccurrences(pvd, "<DataSet "), expected.size());
  const GridSpec& g = expected.grid;
  const auto [nx, ny, nz] = g.cells;
  const bool flat = g.dimension == 2;
  const std::string extent = "0 " + std::to_string(nx) + " 0 " + std::to_string(ny) + " 0 " +
                             std::to_string(flat ? 0 : nz);
  std::size_t p = 0;
  for (std::size_t f = 0; f < expected.size(); ++f) {
    p = pvd.find("<DataSet ", p);
    ASSERT_NE(p, std::string::npos);
    char name[64];
    std::snprintf(name, sizeof(name), "%s_%06zu.vti", prefix.c_str(), f);
    EXPECT_EQ(AttributeValue(pvd, "file", p), name);
    EXPECT_EQ(std::stod(AttributeValue(pvd, "timestep", p)), expected.times[f]);
    ++p;
    const std::string vti = ReadText(dir / name);
    EXPECT_EQ(XmlNestingError(vti), "") << name;
    EXPECT_NE(vti.find("type=\"ImageData\""), std::string::npos);
    EXPECT_EQ(AttributeValue(vti, "WholeExtent"), extent);
    EXPECT_EQ(AttributeValue(vti, "Extent", vti.find("<Piece")), extent);
    std::istringstream origin(AttributeValue(vti, "Origin")),
        spacing(AttributeValue(vti, "Spacing"));
    for (int a = 0; a < 3; ++a) {
      double o = 0, h = 0;
      origin >> o;
      spacing >> h;
      EXPECT_EQ(o, a < g.dimension ? g.origin[a] : 0.0) << name << " axis " << a;
      EXPECT_EQ(h, g.spacing);
    }
    EXPECT_EQ(AttributeValue(vti, "Scalars", vti.find("<CellData")), "c");
    EXPECT_TRUE(SameBits(VtuArray<double>(vti, "c", "Float64", 1), expected.c[f])) << name;
    EXPECT_TRUE(SameBits(VtuArray<double>(vti, "noise", "Float64", 1), expected.noise[f])) << name;
    EXPECT_EQ(
        std::stod(Between(vti, "Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">", "<")),
        expected.times[f]);
  }
}

void ExpectVtiRoundTrip(const GridSpec& grid, std::uint64_t seed) {
  TempDir dir;
  const GridFrames frames = MakeFrames(grid, kTimes, seed);
  WriteGridFrames(*MakeVtiSeriesWriter(dir.path(), "fields", frames.grid), frames);
  ExpectVtiSeriesMatches(dir.path(), "fields", frames);
}

TEST(VtiSeriesWriter, WritesEveryValueBitForBit2D) { ExpectVtiRoundTrip(Grid2D(), 7); }
TEST(VtiSeriesWriter, WritesEveryValueBitForBit3D) { ExpectVtiRoundTrip(Grid3D(), 8); }

TEST(GridWriters, TheSameFramesGiveTheSameBytes) {
  TempDir a, b;
  const GridFrames frames = MakeFrames(Grid3D(), kTimes, 9);
  for (const TempDir* dir : {&a, &b}) {
    WriteGridFrames(*MakeHdf5GridWriter(dir->path() / "fields.h5", frames.grid), frames);
    WriteGridFrames(*MakeVtiSeriesWriter(dir->path(), "fields", frames.grid), frames);
  }
  for (const char* name : {"fields.h5", "fields.xdmf", "fields.pvd", "fields_000002.vti"}) {
    const std::string bytes = ReadText(a.path() / name);
    EXPECT_FALSE(bytes.empty()) << name;
    EXPECT_EQ(bytes, ReadText(b.path() / name)) << name;
  }
}

// --- Bad grids, bad frames, failing writes ------------------------------------------------------

// Runs `make` and expects an InputError whose message names `file` and holds `needle`.
void ExpectInputError(const std::function<void()>& make, const fs::path& file,
                      const std::string& needle) {
  try {
    make();
    ADD_FAILURE() << "expected InputError with " << needle;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(GridWriters, BadGridsThrowBeforeAnyFileIsMade) {
  TempDir dir;
  const fs::path h5 = dir.path() / "fields.h5", pvd = dir.path() / "fields.pvd";
  const std::vector<std::pair<GridSpec, std::string>> bad = {
      {{4, {0, 0, 0}, 1.0, {2, 2, 2}}, "dimension: must be 2 or 3, got 4"},
      {{2, {0, 0, 0}, std::nan(""), {2, 2, 1}}, "spacing: must be finite and > 0, got nan"},
      {{3, {0, 0, 0}, 0.0, {2, 2, 2}}, "spacing: must be finite and > 0, got 0"},
      {{3, {0, 0, 0}, std::numeric_limits<double>::infinity(), {2, 2, 2}}, "spacing"},
      {{3, {0, 1.0 / 0.0, 0}, 1.0, {2, 2, 2}}, "origin: y must be finite, got inf"},
      {{3, {0, 0, 0}, 1.0, {2, 0, 2}}, "cells: n_y must be ≥ 1, got 0"},
      {{2, {0, 0, 0}, 1.0, {2, 2, 3}}, "cells: n_z must be 1 in 2D, got 3"},
  };
  for (const auto& entry : bad) {
    const GridSpec& grid = entry.first;
    const auto& needle = entry.second;
    ExpectInputError([&] { MakeHdf5GridWriter(h5, grid); }, h5, needle);
    ExpectInputError([&] { MakeVtiSeriesWriter(dir.path(), "fields", grid); }, pvd, needle);
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
  // In 2D the z entries of the origin are not used: any value passes.
  GridSpec flat = Grid2D();
  flat.origin[2] = std::nan("");
  EXPECT_NO_THROW(flat.Validate());
  EXPECT_EQ(flat.voxel_count(), 48);
  EXPECT_EQ(Grid3D().voxel_count(), 60);
}

TEST(GridWriters, BadPathsThrowNamingThePath) {
  TempDir dir;
  const fs::path missing = dir.path() / "no_such_dir" / "fields.h5";
  ExpectInputError([&] { MakeHdf5GridWriter(missing, Grid2D()); }, missing, "does not exist");
  const fs::path xdmf = dir.path() / "fields.xdmf";
  ExpectInputError([&] { MakeHdf5GridWriter(xdmf, Grid2D()); }, xdmf, "must not end in .xdmf");
  ExpectInputError([&] { MakeVtiSeriesWriter(dir.path() / "none", "f", Grid2D()); },
                   dir.path() / "none", "does not exist");
  EXPECT_THROW(MakeVtiSeriesWriter(dir.path(), "a/b", Grid2D()), InputError);
  EXPECT_THROW(MakeVtiSeriesWriter(dir.path(), "", Grid2D()), InputError);
}

// Each bad frame throws InputError naming the file; the good frames around them are kept.
void ExpectBadFramesRejected(GridWriter& writer, const fs::path& file, const GridFrames& frames) {
  const std::vector<double> short_values(frames.c[0].begin(), frames.c[0].end() - 1);
  auto bad = [&](std::vector<GridArray> arrays, double time, const std::string& needle) {
    ExpectInputError([&] { writer.Write({99, time, arrays}); }, file, needle);
  };
  const std::vector<double>& c = frames.c[0];
  bad({}, 0.0, "has no fields");
  bad({{"c", short_values}}, 0.0, "field c has 47 values, the grid 48 voxels");
  bad({{"c", c}, {"c", c}}, 0.0, "field name c is used twice");
  for (const char* name : {"", ".", "..", "a/b", "a:b", "a b", "tab\t", "back\\slash"}) {
    bad({{name, c}}, 0.0, "must be non-empty");
  }
  bad({{"c", c}}, std::nan(""), "non-finite time");
  writer.Write(frames.frame(0));
  writer.Write(frames.frame(1));
  bad({{"c", c}, {"noise", c}}, 0.4, "has time 0.4 before the previous frame's 0.5");
  bad({{"c", c}}, 2.0, "other fields than the first frame (c, noise)");
  bad({{"noise", c}, {"c", c}}, 2.0, "other fields than the first frame");
  bad({{"c", c}, {"other", c}}, 2.0, "other fields than the first frame");
  writer.Write(frames.frame(2));
  writer.Close();
  writer.Close();
  EXPECT_THROW(writer.Write(frames.frame(2)), std::logic_error);
}

TEST(Hdf5GridWriter, RejectsBadFramesAndKeepsTheGoodOnes) {
  TempDir dir;
  const GridFrames frames = MakeFrames(Grid2D(), kTimes, 10);
  const fs::path path = dir.path() / "fields.h5";
  ExpectBadFramesRejected(*MakeHdf5GridWriter(path, frames.grid), path, frames);
  ExpectGridHdf5Matches(path, frames);
  ExpectGridXdmfMatches(dir.path() / "fields.xdmf", frames);
}

TEST(VtiSeriesWriter, RejectsBadFramesAndKeepsTheGoodOnes) {
  TempDir dir;
  const GridFrames frames = MakeFrames(Grid2D(), kTimes, 11);
  auto writer = MakeVtiSeriesWriter(dir.path(), "fields", frames.grid);
  // A bad frame names the file it would have been written to.
  ExpectBadFramesRejected(*writer, dir.path() / "fields_00000", frames);
  ExpectVtiSeriesMatches(dir.path(), "fields", frames);
  EXPECT_FALSE(fs::exists(dir.path() / "fields_000003.vti"));
}

// Makes every write past `bytes` of a file fail with EFBIG (as a full disk fails with ENOSPC)
// while it lives; SIGXFSZ, which would end the process, is ignored meanwhile.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    previous_ = std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{bytes, saved_.rlim_max};
    ok_ = setrlimit(RLIMIT_FSIZE, &limit) == 0;
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
  bool ok() const { return ok_; }

 private:
  rlimit saved_{};
  void (*previous_)(int) = SIG_DFL;
  bool ok_ = false;
};

// Writes until a write fails; expects a std::runtime_error (not an InputError) naming `file`.
void ExpectFullDiskError(GridWriter& writer, const GridFrames& frames, const fs::path& file) {
  try {
    for (int f = 0; f < 50; ++f) writer.Write({f, 1.0 * f, frames.arrays[0]});
    writer.Close();
    ADD_FAILURE() << "expected a failing write";
  } catch (const InputError& e) {
    ADD_FAILURE() << "a failing write is not bad input: " << e.what();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(GridWriters, AFullDiskThrowsNamingTheFile) {
  TempDir dir;
  const GridFrames frames = MakeFrames({3, {0, 0, 0}, 1.0, {16, 16, 16}}, {0.0}, 12);
  const fs::path h5 = dir.path() / "fields.h5";
  auto hdf5 = MakeHdf5GridWriter(h5, frames.grid);
  auto vti = MakeVtiSeriesWriter(dir.path(), "fields", frames.grid);
  {
    FileSizeLimit limit(16 * 1024);  // a frame is 32 KiB (HDF5), 44 KiB (VTI)
    ASSERT_TRUE(limit.ok());
    ExpectFullDiskError(*hdf5, frames, h5);
    ExpectFullDiskError(*vti, frames, dir.path() / "fields_00000");
  }
  hdf5.reset();  // the destructors swallow the errors of closing a broken file
  vti.reset();
}

// --- The client suite's samples -----------------------------------------------------------------

// Writes DIR/fields.h5 (+ .xdmf), DIR/vti/fields.pvd (+ .vti) and DIR/trajectory.h5 (+ .xdmf):
// `frames`, and three particles at the same times inside the grid (radius 0.3, id 7, 8, 9).
void WriteSample(const fs::path& dir, const GridFrames& frames) {
  fs::create_directories(dir / "vti");
  WriteGridFrames(*MakeHdf5GridWriter(dir / "fields.h5", frames.grid), frames);
  WriteGridFrames(*MakeVtiSeriesWriter(dir / "vti", "fields", frames.grid), frames);
  const GridSpec& g = frames.grid;
  const int k = g.dimension;
  auto particles = MakeHdf5Writer(dir / "trajectory.h5");
  const std::vector<std::int64_t> ids{7, 8, 9};
  const std::vector<double> radii(3, 0.3);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    std::vector<double> x;
    for (int p = 0; p < 3; ++p) {
      for (int a = 0; a < k; ++a) {
        const double extent = g.spacing * g.cells[a];
        x.push_back(g.origin[a] + extent * (0.25 + 0.25 * p) + 0.05 * static_cast<double>(f));
      }
    }
    particles->Write({frames.steps[f], frames.times[f], k, x.data(), ids.data(), radii.data(), 3});
  }
  particles->Close();
}

// With MOREAU_IO_SAMPLE_DIR set, leaves SAMPLE/fields2d and SAMPLE/fields3d for tests/clients
// (test_field_clients.py) and tests/cli (test_plot_field_cli.py): field c = x + 2y + 3z + t.
TEST(FieldSample, WritesTheFieldsAndParticlesOfA2DAnd3DRun) {
  TempDir dir;
  const char* target = std::getenv("MOREAU_IO_SAMPLE_DIR");
  const fs::path root = target != nullptr ? fs::path(target) : dir.path();
  for (const GridSpec& grid : {Grid2D(), Grid3D()}) {
    const GridFrames frames = MakeFrames(grid, kTimes, 13);
    const fs::path out = root / (grid.dimension == 2 ? "fields2d" : "fields3d");
    WriteSample(out, frames);
    ExpectGridHdf5Matches(out / "fields.h5", frames);
    ExpectVtiSeriesMatches(out / "vti", "fields", frames);
    EXPECT_TRUE(fs::is_regular_file(out / "trajectory.xdmf"));
  }
}

}  // namespace
}  // namespace moreau::io
