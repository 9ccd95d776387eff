// Trajectory writers: HDF5 read back bit for bit through the HDF5 C API, the XDMF sidecar, the
// VTU files decoded from base64, the PVD index, extra point arrays and string lists, the errors;
// and the scene geometry file (geometry.vtp).
#include "moreau/io/trajectory.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

// moreau links HDF5 privately, so its include directory does not reach the tests; Debian keeps
// the headers in hdf5/serial/ (their own includes are relative, so this path works).
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif

#include "io/io_test_util.h"
#include "io/io_util.h"
#include "moreau/common/error.h"
#include "moreau/io/geometry.h"

namespace moreau::io {
namespace {

namespace fs = std::filesystem;
using namespace test_util;  // NOLINT(google-build-using-namespace)

// Frames with their own storage; frame(i) views frame i.
struct FrameSet {
  int dimension = 2;
  std::vector<std::int64_t> counts;  // N of each frame
  std::vector<std::int64_t> steps;
  std::vector<double> times;
  std::vector<std::vector<double>> positions, radii;
  std::vector<std::vector<std::int64_t>> ids;

  std::size_t size() const { return times.size(); }
  std::int64_t largest_count() const {
    return counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());
  }
  ParticleFrame frame(std::size_t i) const {
    ParticleFrame f;
    f.step = steps[i];
    f.time = times[i];
    f.dimension = dimension;
    f.positions = positions[i].data();
    f.ids = ids[i].data();
    f.radii = radii[i].data();
    f.count = counts[i];
    return f;
  }
};

// One frame per entry of `counts` (its N) in dimension k with random (seeded) values, including
// awkward doubles (negative zero, subnormal, large exponents) to check bit-exact storage; ids are
// a shuffled set of stable numbers.
FrameSet RandomFramesWithCounts(int k, const std::vector<std::int64_t>& counts,
                                std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::uniform_real_distribution<double> r(0.01, 0.5);
  FrameSet s;
  s.dimension = k;
  s.counts = counts;
  double t = 0.0;
  for (std::size_t f = 0; f < counts.size(); ++f) {
    const auto n = static_cast<std::size_t>(counts[f]);
    s.steps.push_back(10 * static_cast<std::int64_t>(f) + 3);
    s.times.push_back(t);
    t += 0.1 * (1.0 + r(rng));  // non-representable decimals
    std::vector<double> x(n * static_cast<std::size_t>(k));
    for (double& v : x) v = u(rng);
    if (x.size() >= 3) {
      x[0] = -0.0;
      x[1] = 4.9e-324;
      x[2] = -1.7976931348623157e308;
    }
    std::vector<double> rad(n);
    for (double& v : rad) v = r(rng);
    std::vector<std::int64_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::int64_t>(1000 + 7 * i);
    std::shuffle(order.begin(), order.end(), rng);
    s.positions.push_back(std::move(x));
    s.radii.push_back(std::move(rad));
    s.ids.push_back(std::move(order));
  }
  return s;
}

// `frames` frames of `count` particles each.
FrameSet RandomFrames(int k, std::int64_t count, int frames, std::uint64_t seed) {
  return RandomFramesWithCounts(
      k, std::vector<std::int64_t>(static_cast<std::size_t>(frames), count), seed);
}

// The rows of `frames` padded to `rows` rows per frame with `fill` (`width` values per row).
template <typename T>
std::vector<T> Padded(const std::vector<std::vector<T>>& frames, std::size_t rows,
                      std::size_t width, T fill) {
  std::vector<T> out;
  for (const std::vector<T>& frame : frames) {
    out.insert(out.end(), frame.begin(), frame.end());
    out.insert(out.end(), rows * width - frame.size(), fill);
  }
  return out;
}

// `positions` as the file stores them with `precision`: rounded to float and back in single.
std::vector<double> Stored(std::vector<double> positions, TrajectoryPrecision precision) {
  if (precision == TrajectoryPrecision::kSingle) {
    for (double& v : positions) v = static_cast<double>(static_cast<float>(v));
  }
  return positions;
}

// Reads `path` back and compares every value of every frame, bit for bit, with `expected`: the
// padded F×N×k arrays (rows past a frame's count read as NaN or id −1), /count, the attributes,
// /connectivity and the per-frame views of /xdmf. With `options`: /positions and its views stored
// as float32 in single precision (the values rounded to float), every dataset shuffled and
// deflated at options.compression when it is > 0.
void ExpectHdf5Matches(const fs::path& path, const FrameSet& expected,
                       const Hdf5TrajectoryOptions& options = {}) {
  H5 file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_GE(file.get(), 0) << path;
  const auto frames = static_cast<hsize_t>(expected.size());
  const auto rows = static_cast<hsize_t>(expected.largest_count());
  const auto k = static_cast<hsize_t>(expected.dimension);

  std::vector<double> time, positions, radii;
  std::vector<std::int64_t> step, count, ids, connectivity;
  const DatasetInfo ti = ReadDataset(file.get(), "/time", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, time);
  const DatasetInfo si = ReadDataset(file.get(), "/step", H5T_NATIVE_INT64, H5T_STD_I64LE, step);
  const DatasetInfo ci = ReadDataset(file.get(), "/count", H5T_NATIVE_INT64, H5T_STD_I64LE, count);
  const bool single = options.precision == TrajectoryPrecision::kSingle;
  const hid_t position_type = single ? H5T_IEEE_F32LE : H5T_IEEE_F64LE;
  const DatasetInfo pi =
      ReadDataset(file.get(), "/positions", H5T_NATIVE_DOUBLE, position_type, positions);
  const DatasetInfo ii = ReadDataset(file.get(), "/ids", H5T_NATIVE_INT64, H5T_STD_I64LE, ids);
  const DatasetInfo ri =
      ReadDataset(file.get(), "/radii", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, radii);
  const DatasetInfo ni =
      ReadDataset(file.get(), "/connectivity", H5T_NATIVE_INT64, H5T_STD_I64LE, connectivity);

  EXPECT_EQ(ti.dims, (std::vector<hsize_t>{frames}));
  EXPECT_EQ(si.dims, (std::vector<hsize_t>{frames}));
  EXPECT_EQ(ci.dims, (std::vector<hsize_t>{frames}));
  EXPECT_EQ(pi.dims, (std::vector<hsize_t>{frames, rows, k}));
  EXPECT_EQ(ii.dims, (std::vector<hsize_t>{frames, rows}));
  EXPECT_EQ(ri.dims, (std::vector<hsize_t>{frames, rows}));
  EXPECT_EQ(ni.dims, (std::vector<hsize_t>{rows}));
  for (const DatasetInfo* info : {&ti, &si, &ci, &pi, &ii, &ri, &ni}) {
    EXPECT_TRUE(info->chunked);
    EXPECT_TRUE(info->file_type_ok);
    ASSERT_FALSE(info->max_dims.empty());
    // Frames and particles unlimited; the coordinate axis of /positions fixed at k.
    for (std::size_t a = 0; a < info->dims.size(); ++a) {
      EXPECT_EQ(info->max_dims[a], info == &pi && a == 2 ? k : H5S_UNLIMITED);
    }
    if (options.compression > 0) {
      EXPECT_EQ(info->filters, (std::vector<H5Z_filter_t>{H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE}));
      EXPECT_EQ(info->deflate_level, static_cast<unsigned>(options.compression));
    } else {
      EXPECT_TRUE(info->filters.empty());
    }
  }

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t n = static_cast<std::size_t>(rows);
  EXPECT_TRUE(SameBits(time, expected.times));
  EXPECT_TRUE(SameBits(step, expected.steps));
  EXPECT_TRUE(SameBits(count, expected.counts));
  EXPECT_TRUE(
      SameBits(positions, Stored(Padded(expected.positions, n, k, nan), options.precision)));
  EXPECT_TRUE(SameBits(radii, Padded(expected.radii, n, 1, nan)));
  EXPECT_TRUE(SameBits(ids, Padded(expected.ids, n, 1, std::int64_t{-1})));
  std::vector<std::int64_t> want_connectivity(n);
  for (std::size_t i = 0; i < n; ++i) want_connectivity[i] = static_cast<std::int64_t>(i);
  EXPECT_EQ(connectivity, want_connectivity);

  EXPECT_EQ(ReadScalarAttribute<int>(file.get(), "dimension", H5T_NATIVE_INT), expected.dimension);
  EXPECT_EQ(ReadScalarAttribute<std::int64_t>(file.get(), "count", H5T_NATIVE_INT64),
            expected.largest_count());
  EXPECT_EQ(ReadScalarAttribute<int>(file.get(), "format_version", H5T_NATIVE_INT), 2);
  EXPECT_EQ(ReadStringAttribute(file.get(), "format"), "moreau-trajectory");

  // The views the XDMF sidecar names: exactly the frame's rows.
  for (std::size_t f = 0; f < expected.size(); ++f) {
    if (expected.counts[f] == 0) continue;
    char group[64];
    std::snprintf(group, sizeof(group), "/xdmf/frame_%06zu/", f);
    const std::string g = group;
    std::vector<double> view_positions, view_radii;
    std::vector<std::int64_t> view_ids, view_connectivity;
    const auto nf = static_cast<hsize_t>(expected.counts[f]);
    EXPECT_EQ(ReadDataset(file.get(), (g + "positions").c_str(), H5T_NATIVE_DOUBLE, position_type,
                          view_positions)
                  .dims,
              (std::vector<hsize_t>{nf, k}));
    ReadDataset(file.get(), (g + "radii").c_str(), H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, view_radii);
    ReadDataset(file.get(), (g + "ids").c_str(), H5T_NATIVE_INT64, H5T_STD_I64LE, view_ids);
    ReadDataset(file.get(), (g + "connectivity").c_str(), H5T_NATIVE_INT64, H5T_STD_I64LE,
                view_connectivity);
    EXPECT_TRUE(SameBits(view_positions, Stored(expected.positions[f], options.precision))) << f;
    EXPECT_TRUE(SameBits(view_radii, expected.radii[f])) << f;
    EXPECT_TRUE(SameBits(view_ids, expected.ids[f])) << f;
    EXPECT_EQ(view_connectivity,
              std::vector<std::int64_t>(want_connectivity.begin(),
                                        want_connectivity.begin() + expected.counts[f]));
  }
}

// Checks the XDMF sidecar against the frames: nesting, one grid per frame with its time, its
// count, and plain HDF items naming the views of its group (no HyperSlab, which ParaView 5.11's
// XDMF 3 readers crash on); the positions' items of Precision `position_bytes`.
void ExpectXdmfMatches(const fs::path& xdmf, const std::string& h5_name, const FrameSet& expected,
                       int position_bytes = 8) {
  ASSERT_TRUE(fs::exists(xdmf)) << xdmf;
  const std::string text = ReadText(xdmf);
  EXPECT_EQ(XmlNestingError(text), "");
  EXPECT_NE(text.find("<Xdmf Version=\"3.0\""), std::string::npos);
  EXPECT_NE(text.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_EQ(text.find("HyperSlab"), std::string::npos);
  const std::string k = std::to_string(expected.dimension);
  // Frames with N = 0 are left out of the sidecar.
  const auto frames = static_cast<std::size_t>(
      std::count_if(expected.counts.begin(), expected.counts.end(), [](auto n) { return n > 0; }));
  EXPECT_EQ(CountOccurrences(text, "<Grid Name=\"frame_"), frames);
  EXPECT_EQ(CountOccurrences(text, "<Time Value="), frames);
  std::size_t p = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (expected.counts[i] == 0) continue;
    char name[64];
    std::snprintf(name, sizeof(name), "<Grid Name=\"frame_%06zu\"", i);
    p = text.find(name, p);
    ASSERT_NE(p, std::string::npos) << name;
    const std::size_t end = text.find("</Grid>", p);
    const std::string grid = text.substr(p, end - p);
    p = end;
    const double t = std::stod(AttributeValue(grid, "Value"));
    EXPECT_TRUE(SameBits(std::vector<double>{t}, std::vector<double>{expected.times[i]})) << i;
    const std::string n = std::to_string(expected.counts[i]);
    EXPECT_NE(grid.find("TopologyType=\"Polyvertex\" NumberOfElements=\"" + n + "\""),
              std::string::npos);
    char group[64];
    std::snprintf(group, sizeof(group), "%s:/xdmf/frame_%06zu/", h5_name.c_str(), i);
    const std::string g = group;
    EXPECT_NE(grid.find("GeometryType=\"" + std::string(k == "2" ? "XY\"" : "XYZ\"")),
              std::string::npos);
    EXPECT_NE(
        grid.find("Dimensions=\"" + n + "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" +
                  g + "connectivity<"),
        std::string::npos);
    EXPECT_NE(grid.find("Dimensions=\"" + n + " " + k + "\" NumberType=\"Float\" Precision=\"" +
                        std::to_string(position_bytes) + "\" Format=\"HDF\">" + g + "positions<"),
              std::string::npos);
    EXPECT_NE(grid.find("<Attribute Name=\"radius\""), std::string::npos);
    EXPECT_NE(grid.find("Dimensions=\"" + n +
                        "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + g + "radii<"),
              std::string::npos);
    EXPECT_NE(grid.find("<Attribute Name=\"id\""), std::string::npos);
    EXPECT_NE(grid.find("Dimensions=\"" + n +
                        "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" + g + "ids<"),
              std::string::npos);
  }
}

// Copies STEM.h5 and STEM.xdmf of `dir` into the directory named by MOREAU_IO_SAMPLE_DIR, when
// set: the client suite (tests/clients) opens them with ParaView's readers.
void KeepSample(const fs::path& dir, const std::string& stem) {
  const char* target = std::getenv("MOREAU_IO_SAMPLE_DIR");
  if (target == nullptr) return;
  for (const char* extension : {".h5", ".xdmf"}) {
    fs::copy_file(dir / (stem + extension), fs::path(target) / (stem + extension),
                  fs::copy_options::overwrite_existing);
  }
}

void WriteAll(TrajectoryWriter& writer, const FrameSet& frames) {
  for (std::size_t i = 0; i < frames.size(); ++i) writer.Write(frames.frame(i));
}

// --- HDF5 ---------------------------------------------------------------------------------------

TEST(Hdf5Writer, RoundTripsEveryValueBitForBit2D) {
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 37, 5, 11);
  const fs::path path = dir.path() / "trajectory.h5";
  auto writer = MakeHdf5Writer(path);
  WriteAll(*writer, frames);
  writer->Close();
  ExpectHdf5Matches(path, frames);
  ExpectXdmfMatches(dir.path() / "trajectory.xdmf", "trajectory.h5", frames);
}

TEST(Hdf5Writer, RoundTripsEveryValueBitForBit3D) {
  TempDir dir;
  const FrameSet frames = RandomFrames(3, 12, 3, 12);
  const fs::path path = dir.path() / "run.h5";
  auto writer = MakeHdf5Writer(path);
  WriteAll(*writer, frames);
  writer->Close();
  writer->Close();  // idempotent
  ExpectHdf5Matches(path, frames);
  ExpectXdmfMatches(dir.path() / "run.xdmf", "run.h5", frames);
}

TEST(Hdf5Writer, LargeFramesSpanSeveralChunks) {
  // 70 000 particles in 2D: 1.1 MB per frame, more than one chunk along the particle axis.
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 70000, 2, 13);
  const fs::path path = dir.path() / "big.h5";
  auto writer = MakeHdf5Writer(path);
  WriteAll(*writer, frames);
  writer->Close();
  ExpectHdf5Matches(path, frames);
}

TEST(Hdf5Writer, DestructorClosesAndWritesTheSidecar) {
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 4, 2, 14);
  {
    auto writer = MakeHdf5Writer(dir.path() / "t.h5");
    WriteAll(*writer, frames);
  }
  ExpectHdf5Matches(dir.path() / "t.h5", frames);
  ExpectXdmfMatches(dir.path() / "t.xdmf", "t.h5", frames);
}

TEST(Hdf5Writer, NoFramesGivesEmptyTimeAxis) {
  TempDir dir;
  MakeHdf5Writer(dir.path() / "empty.h5")->Close();
  H5 file(H5Fopen((dir.path() / "empty.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_GE(file.get(), 0);
  std::vector<double> time;
  const DatasetInfo info =
      ReadDataset(file.get(), "/time", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, time);
  EXPECT_EQ(info.dims, (std::vector<hsize_t>{0}));
  const std::string xdmf = ReadText(dir.path() / "empty.xdmf");
  EXPECT_EQ(XmlNestingError(xdmf), "");
  EXPECT_EQ(CountOccurrences(xdmf, "<Grid Name=\"frame_"), 0u);
}

// Writes `frames` to STEM.h5 in a fresh directory, reads everything back, keeps the sample.
void ExpectRoundTrip(const FrameSet& frames, const std::string& stem,
                     const Hdf5TrajectoryOptions& options = {}) {
  TempDir dir;
  const fs::path path = dir.path() / (stem + ".h5");
  auto writer = MakeHdf5Writer(path, options);
  WriteAll(*writer, frames);
  writer->Close();
  ExpectHdf5Matches(path, frames, options);
  const int position_bytes = options.precision == TrajectoryPrecision::kSingle ? 4 : 8;
  ExpectXdmfMatches(dir.path() / (stem + ".xdmf"), stem + ".h5", frames, position_bytes);
  KeepSample(dir.path(), stem);
}

TEST(Hdf5Writer, ChangingParticleCountRoundTripsPaddedWithViews) {
  // Growing, dividing, dying and an empty frame: rows past a frame's count read as padding, the
  // views show exactly the frame's rows.
  ExpectRoundTrip(RandomFramesWithCounts(2, {0, 3, 5, 5, 2, 0, 9, 4}, 15), "t");
}

TEST(Hdf5Writer, GrowingPastOneChunkOfParticlesRoundTrips3D) {
  ExpectRoundTrip(RandomFramesWithCounts(3, {1, 40, 70, 200, 130}, 16), "grow");
}

// Frames of changing count whose coordinates all fit in a float (the random frames' −1.8·10^308
// would round to −inf, which single precision does not promise to keep).
FrameSet FloatRangeFrames(int k, const std::vector<std::int64_t>& counts, std::uint64_t seed) {
  FrameSet frames = RandomFramesWithCounts(k, counts, seed);
  for (std::vector<double>& x : frames.positions) {
    for (double& v : x) v = std::clamp(v, -1e30, 1e30);
  }
  return frames;
}

TEST(Hdf5Writer, SinglePrecisionStoresFloat32PositionsAndTheSidecarSaysSo) {
  // Positions rounded to float (subnormal doubles to ±0, padding NaN), everything else exact.
  ExpectRoundTrip(FloatRangeFrames(2, {3, 5, 0, 70, 4}, 31), "single",
                  {TrajectoryPrecision::kSingle, 0});
  ExpectRoundTrip(FloatRangeFrames(3, {40, 200, 7}, 32), "single3d",
                  {TrajectoryPrecision::kSingle, 0});
}

TEST(Hdf5Writer, CompressionShufflesAndDeflatesEveryDatasetLosslessly) {
  ExpectRoundTrip(RandomFramesWithCounts(2, {3, 5, 0, 70, 4}, 33), "deflate",
                  {TrajectoryPrecision::kDouble, 6});
  ExpectRoundTrip(FloatRangeFrames(3, {1, 200, 130}, 34), "single_deflate",
                  {TrajectoryPrecision::kSingle, 9});
}

TEST(Hdf5Writer, CompressionShrinksRepetitiveData) {
  // Equal radii: 4096 equal doubles per frame deflate to a small fraction of their 32 KiB.
  TempDir dir;
  FrameSet frames = RandomFrames(2, 4096, 2, 35);
  for (std::vector<double>& r : frames.radii) std::fill(r.begin(), r.end(), 0.5);
  std::vector<hsize_t> radii_bytes;
  for (const int level : {0, 1}) {
    const fs::path path = dir.path() / ("level" + std::to_string(level) + ".h5");
    auto writer = MakeHdf5Writer(path, {TrajectoryPrecision::kDouble, level});
    WriteAll(*writer, frames);
    writer->Close();
    H5 file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    std::vector<double> radii;
    radii_bytes.push_back(
        ReadDataset(file.get(), "/radii", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, radii).storage_bytes);
    EXPECT_TRUE(SameBits(radii, Padded(frames.radii, 4096, 1, 0.0)));
  }
  EXPECT_GE(radii_bytes[0], 2u * 4096u * 8u);
  EXPECT_LT(radii_bytes[1] * 20, radii_bytes[0]);
}

TEST(Hdf5Writer, OptionsOutOfRangeThrowNamingTheField) {
  TempDir dir;
  for (const int level : {-1, 10}) {
    const Hdf5TrajectoryOptions options{TrajectoryPrecision::kDouble, level};
    try {
      MakeHdf5Writer(dir.path() / "t.h5", options);
      FAIL() << "expected InputError for compression " << level;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("compression"), std::string::npos) << message;
      EXPECT_NE(message.find(std::to_string(level)), std::string::npos) << message;
    }
  }
  EXPECT_FALSE(fs::exists(dir.path() / "t.h5"));  // nothing written
  for (const int level : {0, 9}) {
    EXPECT_NO_THROW((Hdf5TrajectoryOptions{TrajectoryPrecision::kSingle, level}.Validate()));
  }
}

TEST(TrajectoryPrecision, NamesRoundTripAndUnknownNamesThrow) {
  for (const TrajectoryPrecision p : {TrajectoryPrecision::kDouble, TrajectoryPrecision::kSingle}) {
    EXPECT_EQ(ParseTrajectoryPrecision(TrajectoryPrecisionName(p)), p);
  }
  EXPECT_EQ(TrajectoryPrecisionName(TrajectoryPrecision::kSingle), "single");
  try {
    ParseTrajectoryPrecision("half");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'half'"), std::string::npos) << e.what();
  }
}

TEST(Hdf5Writer, ChangingDimensionThrows) {
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 6, 1, 17);
  const FrameSet other = RandomFrames(3, 6, 1, 18);
  auto writer = MakeHdf5Writer(dir.path() / "t.h5");
  writer->Write(frames.frame(0));
  ParticleFrame bad = other.frame(0);
  bad.time = 1.0;
  EXPECT_THROW(writer->Write(bad), InputError);
  writer->Close();
  ExpectHdf5Matches(dir.path() / "t.h5", frames);  // the frames before it stay
}

TEST(Hdf5Writer, RejectsBadFrames) {
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 3, 2, 19);
  auto writer = MakeHdf5Writer(dir.path() / "t.h5");
  ParticleFrame f = frames.frame(0);
  f.dimension = 4;
  EXPECT_THROW(writer->Write(f), InputError);
  f = frames.frame(0);
  f.radii = nullptr;
  EXPECT_THROW(writer->Write(f), InputError);
  writer->Write(frames.frame(1));
  EXPECT_THROW(writer->Write(frames.frame(0)), InputError);  // time goes backwards
  writer->Close();
  EXPECT_THROW(writer->Write(frames.frame(1)), std::logic_error);
}

TEST(Hdf5Writer, MissingDirectoryThrowsNamingThePath) {
  TempDir dir;
  const fs::path path = dir.path() / "no_such_dir" / "trajectory.h5";
  try {
    MakeHdf5Writer(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  // A regular file where the directory should be.
  { std::ofstream(dir.path() / "file") << "x"; }
  const fs::path under_file = dir.path() / "file" / "trajectory.h5";
  try {
    MakeHdf5Writer(under_file);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(under_file.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(MakeHdf5Writer(dir.path() / "t.xdmf"), InputError);
}

TEST(Hdf5Writer, UnwritableDirectoryThrowsNamingThePath) {
  if (::geteuid() == 0) GTEST_SKIP() << "root can write into any directory";
  TempDir dir;
  const fs::path locked = dir.path() / "locked";
  fs::create_directory(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  const fs::path path = locked / "trajectory.h5";
  try {
    MakeHdf5Writer(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  fs::permissions(locked, fs::perms::owner_all);
}

// --- VTU series ---------------------------------------------------------------------------------

void ExpectVtuSeriesMatches(const fs::path& dir, const std::string& prefix,
                            const FrameSet& expected) {
  const std::string pvd = ReadText(dir / (prefix + ".pvd"));
  EXPECT_EQ(XmlNestingError(pvd), "");
  EXPECT_NE(pvd.find("type=\"Collection\""), std::string::npos);
  EXPECT_EQ(CountOccurrences(pvd, "<DataSet "), expected.size());
  std::size_t p = 0;
  for (std::size_t f = 0; f < expected.size(); ++f) {
    p = pvd.find("<DataSet ", p);
    ASSERT_NE(p, std::string::npos);
    char name[64];
    std::snprintf(name, sizeof(name), "%s_%06zu.vtu", prefix.c_str(), f);
    EXPECT_EQ(AttributeValue(pvd, "file", p), name);
    const double t = std::stod(AttributeValue(pvd, "timestep", p));
    EXPECT_TRUE(SameBits(std::vector<double>{t}, std::vector<double>{expected.times[f]}));
    ++p;

    const std::string vtu = ReadText(dir / name);
    EXPECT_EQ(XmlNestingError(vtu), "") << name;
    EXPECT_NE(vtu.find("type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(vtu.find("header_type=\"UInt64\""), std::string::npos);
    const std::size_t n = static_cast<std::size_t>(expected.counts[f]);
    const std::size_t k = static_cast<std::size_t>(expected.dimension);
    EXPECT_EQ(AttributeValue(vtu, "NumberOfPoints"), std::to_string(n));
    EXPECT_EQ(AttributeValue(vtu, "NumberOfCells"), std::to_string(n));
    std::vector<double> points(3 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t a = 0; a < k; ++a) points[3 * i + a] = expected.positions[f][k * i + a];
    }
    EXPECT_TRUE(SameBits(VtuArray<double>(vtu, "Points", "Float64", 3), points)) << name;
    EXPECT_TRUE(SameBits(VtuArray<double>(vtu, "radius", "Float64", 1), expected.radii[f]));
    EXPECT_TRUE(SameBits(VtuArray<std::int64_t>(vtu, "id", "Int64", 1), expected.ids[f]));
    std::vector<std::int64_t> connectivity(n), offsets(n);
    for (std::size_t i = 0; i < n; ++i) {
      connectivity[i] = static_cast<std::int64_t>(i);
      offsets[i] = static_cast<std::int64_t>(i + 1);
    }
    EXPECT_TRUE(SameBits(VtuArray<std::int64_t>(vtu, "connectivity", "Int64", 1), connectivity));
    EXPECT_TRUE(SameBits(VtuArray<std::int64_t>(vtu, "offsets", "Int64", 1), offsets));
    EXPECT_TRUE(SameBits(VtuArray<std::uint8_t>(vtu, "types", "UInt8", 1),
                         std::vector<std::uint8_t>(n, 1)));  // VTK_VERTEX
    const std::size_t tv = vtu.find("Name=\"TimeValue\"");
    ASSERT_NE(tv, std::string::npos);
    const std::size_t body = vtu.find('>', tv) + 1;
    EXPECT_EQ(std::stod(vtu.substr(body, vtu.find('<', body) - body)), expected.times[f]);
  }
}

TEST(VtuSeriesWriter, WritesEveryValueBitForBit2D) {
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 23, 4, 21);
  auto writer = MakeVtuSeriesWriter(dir.path(), "disks");
  WriteAll(*writer, frames);
  writer->Close();
  writer->Close();
  ExpectVtuSeriesMatches(dir.path(), "disks", frames);
}

TEST(VtuSeriesWriter, WritesEveryValueBitForBit3D) {
  TempDir dir;
  const FrameSet frames = RandomFrames(3, 10, 3, 22);
  {
    auto writer = MakeVtuSeriesWriter(dir.path(), "grains");
    WriteAll(*writer, frames);
  }  // the destructor completes the PVD
  ExpectVtuSeriesMatches(dir.path(), "grains", frames);
}

TEST(VtuSeriesWriter, AllowsTheParticleCountToChange) {
  TempDir dir;
  const FrameSet a = RandomFrames(2, 8, 1, 23);
  const FrameSet b = RandomFrames(2, 5, 1, 24);
  const FrameSet empty = RandomFrames(2, 0, 1, 25);
  auto writer = MakeVtuSeriesWriter(dir.path(), "crowd");
  writer->Write(a.frame(0));
  ParticleFrame fb = b.frame(0);
  fb.time = 1.0;
  writer->Write(fb);
  ParticleFrame fe = empty.frame(0);
  fe.time = 2.0;
  writer->Write(fe);
  writer->Close();
  EXPECT_EQ(AttributeValue(ReadText(dir.path() / "crowd_000001.vtu"), "NumberOfPoints"), "5");
  const std::string last = ReadText(dir.path() / "crowd_000002.vtu");
  EXPECT_EQ(AttributeValue(last, "NumberOfPoints"), "0");
  EXPECT_TRUE(VtuArray<double>(last, "radius", "Float64", 1).empty());
  EXPECT_EQ(CountOccurrences(ReadText(dir.path() / "crowd.pvd"), "<DataSet "), 3u);
}

TEST(VtuSeriesWriter, RejectsBadFramesAndWriteAfterClose) {
  TempDir dir;
  const FrameSet frames = RandomFrames(2, 3, 2, 26);
  auto writer = MakeVtuSeriesWriter(dir.path(), "p");
  ParticleFrame f = frames.frame(0);
  f.dimension = 1;
  EXPECT_THROW(writer->Write(f), InputError);
  writer->Write(frames.frame(1));
  EXPECT_THROW(writer->Write(frames.frame(0)), InputError);  // time goes backwards
  writer->Close();
  EXPECT_THROW(writer->Write(frames.frame(1)), std::logic_error);
}

TEST(VtuSeriesWriter, MissingDirectoryOrBadPrefixThrows) {
  TempDir dir;
  const fs::path missing = dir.path() / "no_such_dir";
  try {
    MakeVtuSeriesWriter(missing, "frames");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(MakeVtuSeriesWriter(dir.path(), ""), InputError);
  EXPECT_THROW(MakeVtuSeriesWriter(dir.path(), "a/b"), InputError);
}

TEST(VtuSeriesWriter, UnwritableDirectoryThrowsNamingThePath) {
  if (::geteuid() == 0) GTEST_SKIP() << "root can write into any directory";
  TempDir dir;
  const fs::path locked = dir.path() / "locked";
  fs::create_directory(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  try {
    MakeVtuSeriesWriter(locked, "frames");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((locked / "frames.pvd").string()), std::string::npos)
        << e.what();
  }
  fs::permissions(locked, fs::perms::owner_all);
}

// --- helpers ------------------------------------------------------------------------------------

TEST(IoUtil, Base64MatchesRfc4648Vectors) {
  const std::vector<std::pair<std::string, std::string>> cases = {{"", ""},
                                                                  {"f", "Zg=="},
                                                                  {"fo", "Zm8="},
                                                                  {"foo", "Zm9v"},
                                                                  {"foob", "Zm9vYg=="},
                                                                  {"fooba", "Zm9vYmE="},
                                                                  {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, encoded] : cases) {
    std::string out = "prefix:";
    internal::AppendBase64(plain.data(), plain.size(), out);
    EXPECT_EQ(out, "prefix:" + encoded);
  }
  std::mt19937 rng(31);
  std::vector<unsigned char> bytes(1001);
  for (auto& b : bytes) b = static_cast<unsigned char>(rng() & 0xFFu);
  std::string out;
  internal::AppendBase64(bytes.data(), bytes.size(), out);
  EXPECT_EQ(DecodeBase64(out), bytes);
}

TEST(IoUtil, XmlEscapeAndShortestDoubles) {
  EXPECT_EQ(internal::XmlEscape("a&b<c>\"d'"), "a&amp;b&lt;c&gt;&quot;d&apos;");
  for (const double v : {0.1, 1.0 / 3.0, 1e-300, -2.5, 4.9e-324, 1.7976931348623157e308}) {
    EXPECT_EQ(std::strtod(internal::FormatDouble(v).c_str(), nullptr), v);
  }
}

}  // namespace
}  // namespace moreau::io

// --- Extra point arrays and string lists --------------------------------------------------------

namespace moreau::io {
namespace {

// The frames' extra arrays: "type" (int64), "age" (float64), "polarity" (3 × float64), with
// values that tell frame f and row i apart.
struct ArrayFrames {
  FrameSet frames;
  std::vector<std::vector<std::int64_t>> type;
  std::vector<std::vector<double>> age, polarity;
  std::vector<std::vector<PointArray>> arrays;

  explicit ArrayFrames(const std::vector<std::int64_t>& counts)
      : frames(RandomFramesWithCounts(2, counts, 31)) {
    for (std::size_t f = 0; f < counts.size(); ++f) {
      const auto n = static_cast<std::size_t>(counts[f]);
      type.emplace_back(n);
      age.emplace_back(n);
      polarity.emplace_back(3 * n);
      for (std::size_t i = 0; i < n; ++i) {
        type[f][i] = static_cast<std::int64_t>(10 * f + i);
        age[f][i] = 0.25 * static_cast<double>(i) + static_cast<double>(f);
        polarity[f][3 * i] = static_cast<double>(i);
        polarity[f][3 * i + 1] = -static_cast<double>(f);
      }
    }
    for (std::size_t f = 0; f < counts.size(); ++f) {
      arrays.push_back({PointArray::Int64("type", type[f].data()),
                        PointArray::Float64("age", age[f].data()),
                        PointArray::Float64("polarity", polarity[f].data(), 3)});
    }
  }
  ParticleFrame frame(std::size_t f) const {
    ParticleFrame out = frames.frame(f);
    out.arrays = arrays[f];
    return out;
  }
};

const std::vector<StringList> kTypeNames{{"type_names", {"normal", "tumour"}}};

TEST(Hdf5Writer, PointArraysAndStringListsRoundTripPaddedWithViews) {
  TempDir dir;
  const ArrayFrames a({3, 5, 0, 4});
  const fs::path path = dir.path() / "agents.h5";
  auto writer = MakeHdf5Writer(path, {}, kTypeNames);
  for (std::size_t f = 0; f < 4; ++f) writer->Write(a.frame(f));
  writer->Close();
  H5 file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_GE(file.get(), 0);
  std::vector<std::int64_t> type;
  std::vector<double> age, polarity;
  DatasetInfo info =
      ReadDataset(file.get(), "/point_data/type", H5T_NATIVE_INT64, H5T_STD_I64LE, type);
  EXPECT_EQ(info.dims, (std::vector<hsize_t>{4, 5}));
  EXPECT_EQ(type, Padded(a.type, 5, 1, std::int64_t{-1}));
  info = ReadDataset(file.get(), "/point_data/age", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, age);
  EXPECT_EQ(info.dims, (std::vector<hsize_t>{4, 5}));
  const std::vector<double> age_padded = Padded(a.age, 5, 1, std::nan(""));
  for (std::size_t i = 0; i < age.size(); ++i) {
    EXPECT_TRUE(age[i] == age_padded[i] || (std::isnan(age[i]) && std::isnan(age_padded[i])));
  }
  info =
      ReadDataset(file.get(), "/point_data/polarity", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, polarity);
  EXPECT_EQ(info.dims, (std::vector<hsize_t>{4, 5, 3}));
  EXPECT_EQ(std::vector<double>(polarity.begin() + 15, polarity.begin() + 30), a.polarity[1]);
  ReadDataset(file.get(), "/xdmf/frame_000003/point_data/polarity", H5T_NATIVE_DOUBLE,
              H5T_IEEE_F64LE, polarity);
  EXPECT_EQ(polarity, a.polarity[3]);
  ReadDataset(file.get(), "/xdmf/frame_000001/point_data/type", H5T_NATIVE_INT64, H5T_STD_I64LE,
              type);
  EXPECT_EQ(type, a.type[1]);
  // type_names: an array of two fixed-length strings.
  H5 attribute(H5Aopen(file.get(), "type_names", H5P_DEFAULT), H5Aclose);
  ASSERT_GE(attribute.get(), 0);
  H5 space(H5Aget_space(attribute.get()), H5Sclose);
  EXPECT_EQ(H5Sget_simple_extent_npoints(space.get()), 2);
  H5 string_type(H5Aget_type(attribute.get()), H5Tclose);
  const std::size_t width = H5Tget_size(string_type.get());
  std::string names(2 * width, '\0');
  ASSERT_GE(H5Aread(attribute.get(), string_type.get(), names.data()), 0);
  EXPECT_EQ(names.substr(0, names.find('\0')), "normal");
  EXPECT_EQ(std::string(names.c_str() + width), "tumour");
  // The sidecar: three node attributes per non-empty frame (three of them).
  const std::string xdmf = ReadText(dir.path() / "agents.xdmf");
  EXPECT_EQ(XmlNestingError(xdmf), "");
  EXPECT_EQ(CountOccurrences(xdmf, "<Attribute Name=\"type\" AttributeType=\"Scalar\""), 3u);
  EXPECT_EQ(CountOccurrences(xdmf, "<Attribute Name=\"polarity\" AttributeType=\"Vector\""), 3u);
  EXPECT_NE(xdmf.find("Dimensions=\"4 3\" NumberType=\"Float\" Precision=\"8\" "
                      "Format=\"HDF\">agents.h5:/xdmf/frame_000003/point_data/polarity<"),
            std::string::npos);
  KeepSample(dir.path(), "agents");
}

TEST(Hdf5Writer, PointArraysKeepTheFirstFramesLayoutAndGoodNames) {
  TempDir dir;
  const ArrayFrames a({2, 2});
  auto writer = MakeHdf5Writer(dir.path() / "t.h5");
  writer->Write(a.frame(0));
  ParticleFrame fewer = a.frame(1);
  fewer.arrays = fewer.arrays.subspan(0, 2);
  EXPECT_THROW(writer->Write(fewer), InputError);
  ParticleFrame bad = a.frame(1);
  std::vector<PointArray> arrays(bad.arrays.begin(), bad.arrays.end());
  for (const char* name : {"radius", "id", "", "a/b"}) {
    arrays[0].name = name;
    bad.arrays = arrays;
    EXPECT_THROW(writer->Write(bad), InputError) << name;
  }
  arrays[0].name = "age";  // used twice
  bad.arrays = arrays;
  EXPECT_THROW(writer->Write(bad), InputError);
  arrays[0] = PointArray::Float64("velocity", a.age[1].data(), 2);
  bad.arrays = arrays;
  EXPECT_THROW(writer->Write(bad), InputError);
  writer->Write(a.frame(1));
  for (const char* name : {"format", "count", ""}) {
    EXPECT_THROW(MakeHdf5Writer(dir.path() / "u.h5", {}, {{name, {}}}), InputError) << name;
  }
}

TEST(VtuSeriesWriter, WritesPointArraysAndStringLists) {
  TempDir dir;
  const ArrayFrames a({3, 0, 4});
  auto writer = MakeVtuSeriesWriter(dir.path(), "agents", kTypeNames);
  for (std::size_t f = 0; f < 3; ++f) writer->Write(a.frame(f));
  writer->Close();
  ExpectVtuSeriesMatches(dir.path(), "agents", a.frames);
  for (std::size_t f = 0; f < 3; ++f) {
    char name[64];
    std::snprintf(name, sizeof(name), "agents_%06zu.vtu", f);
    const std::string vtu = ReadText(dir.path() / name);
    EXPECT_EQ(VtuArray<std::int64_t>(vtu, "type", "Int64", 1), a.type[f]);
    EXPECT_EQ(VtuArray<double>(vtu, "age", "Float64", 1), a.age[f]);
    EXPECT_EQ(VtuArray<double>(vtu, "polarity", "Float64", 3), a.polarity[f]);
    // "normal" and "tumour" as VTK writes a string array: bytes as numbers, each ended by 0.
    EXPECT_NE(vtu.find("<Array type=\"String\" Name=\"type_names\" NumberOfTuples=\"2\" "
                       "format=\"ascii\">\n        110 111 114 109 97 108 0 116 117 109 111 117 "
                       "114 0\n      </Array>"),
              std::string::npos);
  }
  auto other = MakeVtuSeriesWriter(dir.path(), "other");
  other->Write(a.frame(0));
  EXPECT_THROW(other->Write(a.frames.frame(2)), InputError);  // the arrays left out
  EXPECT_THROW(MakeVtuSeriesWriter(dir.path(), "x", {{"step", {}}}), InputError);
}

}  // namespace
}  // namespace moreau::io

// --- Scene geometry -----------------------------------------------------------------------------

namespace moreau::io {
namespace {

// The text between the tags of the DataArray `name` that follows `from`.
std::string AsciiArray(const std::string& text, const std::string& name, std::size_t from = 0) {
  const std::size_t p = text.find("Name=\"" + name + "\"", from);
  if (p == std::string::npos) return "missing";
  const std::size_t body = text.find('>', p) + 1;
  std::istringstream in(text.substr(body, text.find('<', body) - body));
  std::string out, word;
  while (in >> word) out += (out.empty() ? "" : " ") + word;
  return out;
}

TEST(GeometryVtp, WritesLinesThenPolygonsWithTheirKinds) {
  TempDir dir;
  SceneGeometry g{{"wall", "sphere", "door"}, {}};
  g.cells.push_back({{{0, 0, 0}, {2, 0, 0}}, 0, 4});
  g.cells.push_back({{{1, 1, 0}, {1.5, 1, 0}, {1, 1.5, 0}}, 1, 7});
  g.cells.push_back({{{2, 0.5, 0}, {2, 1.25, 0}}, 2, 0});
  const fs::path path = dir.path() / "geometry.vtp";
  WriteGeometryVtp(path, g);
  const std::string vtp = ReadText(path);
  EXPECT_EQ(XmlNestingError(vtp), "");
  EXPECT_EQ(AttributeValue(vtp, "NumberOfPoints"), "7");
  EXPECT_EQ(AttributeValue(vtp, "NumberOfLines"), "2");
  EXPECT_EQ(AttributeValue(vtp, "NumberOfPolys"), "1");
  EXPECT_EQ(AsciiArray(vtp, "kind"), "0 2 1");  // lines first, then the polygon
  EXPECT_EQ(AsciiArray(vtp, "index"), "4 0 7");
  EXPECT_EQ(AsciiArray(vtp, "Points"), "0 0 0 2 0 0 1 1 0 1.5 1 0 1 1.5 0 2 0.5 0 2 1.25 0");
  const std::size_t lines = vtp.find("<Lines>"), polys = vtp.find("<Polys>");
  EXPECT_EQ(AsciiArray(vtp, "connectivity", lines), "0 1 5 6");
  EXPECT_EQ(AsciiArray(vtp, "offsets", lines), "2 4");
  EXPECT_EQ(AsciiArray(vtp, "connectivity", polys), "2 3 4");
  EXPECT_EQ(AsciiArray(vtp, "offsets", polys), "3");
  EXPECT_NE(vtp.find("Name=\"kind_names\" NumberOfTuples=\"3\""), std::string::npos);
  g.cells.push_back({{{0, 0, 0}}, 0, 0});  // one point
  EXPECT_THROW(WriteGeometryVtp(path, g), InputError);
  g.cells.back() = {{{0, 0, 0}, {1, 0, 0}}, 3, 0};  // no kind 3
  EXPECT_THROW(WriteGeometryVtp(path, g), InputError);
}

}  // namespace
}  // namespace moreau::io
