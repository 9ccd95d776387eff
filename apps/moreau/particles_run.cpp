#include "particles_run.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <memory>
#include <limits>
#include <span>
#include <optional>

#include "moreau/common/error.h"
#include "moreau/common/hash.h"
#include "moreau/common/random.h"
#include "moreau/common/steps.h"
#include "moreau/io/trajectory.h"
#include "moreau/particles/engine.h"
#include "moreau/particles/room.h"
#include "output.h"
#include "progress.h"

namespace moreau::cli {
namespace {

using particles::Vec3;

// Runs `fn`, turning an InputError into "FILE: KEY: REASON".
template <class Fn>
auto WithKey(const Scenario& s, std::string_view key, Fn&& fn) {
  try {
    return fn();
  } catch (const InputError& e) {
    s.Fail(key, e.what());
  }
}

Vec3 ReadVec(Scenario& s, const std::string& key, int k, const Vec3& fallback) {
  if (!s.Has(key)) {
    s.GetNode(key);
    return fallback;
  }
  const std::vector<double> v = s.GetDoubleArray(key, {});
  if (static_cast<int>(v.size()) != k) {
    s.Fail(key, fmt::format("expected {} numbers (the dimension), got {}", k, v.size()));
  }
  Vec3 out{0.0, 0.0, 0.0};
  for (int a = 0; a < k; ++a) out[static_cast<std::size_t>(a)] = v[static_cast<std::size_t>(a)];
  return out;
}

Vec3 VecFromNode(const Scenario& s, const std::string& key, const toml::node* node, int k) {
  const toml::array* arr = node ? node->as_array() : nullptr;
  if (arr == nullptr || static_cast<int>(arr->size()) != k) {
    s.Fail(key, fmt::format("expected an array of {} numbers", k));
  }
  Vec3 out{0.0, 0.0, 0.0};
  for (int a = 0; a < k; ++a) {
    const auto v = (*arr)[static_cast<std::size_t>(a)].value<double>();
    if (!v || !std::isfinite(*v)) s.Fail(key, "entries must be finite numbers");
    out[static_cast<std::size_t>(a)] = *v;
  }
  return out;
}

double NumberFromTable(const Scenario& s, const std::string& key, const toml::table& t,
                       const char* field) {
  const auto v = t[field].value<double>();
  if (!v || !std::isfinite(*v)) s.Fail(key + "." + field, "expected a finite number");
  return *v;
}

// Arrays of tables: [[walls]], [[spheres]], [[segments]].
void ReadObstacles(Scenario& s, particles::ParticleModel* model) {
  const int k = model->dimension;
  const auto tables = [&](const std::string& key) {
    std::vector<const toml::table*> out;
    const toml::node* node = s.GetNode(key);
    if (node == nullptr) return out;
    const toml::array* arr = node->as_array();
    if (arr == nullptr) s.Fail(key, "expected an array of tables ([[" + key + "]])");
    for (const toml::node& item : *arr) {
      if (item.as_table() == nullptr) s.Fail(key, "expected an array of tables");
      out.push_back(item.as_table());
    }
    return out;
  };
  const auto tables_walls = tables("walls");
  for (std::size_t w = 0; w < tables_walls.size(); ++w) {
    const std::string key = fmt::format("walls[{}]", w);
    particles::Wall wall;
    wall.normal = VecFromNode(s, key + ".normal", tables_walls[w]->get("normal"), k);
    wall.offset = NumberFromTable(s, key, *tables_walls[w], "offset");
    model->walls.push_back(wall);
  }
  const auto tables_spheres = tables("spheres");
  for (std::size_t i = 0; i < tables_spheres.size(); ++i) {
    const std::string key = fmt::format("spheres[{}]", i);
    particles::SphereObstacle sphere;
    sphere.center = VecFromNode(s, key + ".center", tables_spheres[i]->get("center"), k);
    sphere.radius = NumberFromTable(s, key, *tables_spheres[i], "radius");
    model->spheres.push_back(sphere);
  }
  const auto tables_segments = tables("segments");
  for (std::size_t i = 0; i < tables_segments.size(); ++i) {
    const std::string key = fmt::format("segments[{}]", i);
    if (k != 2) s.Fail(key, "segments need dimension 2");
    const Vec3 a = VecFromNode(s, key + ".a", tables_segments[i]->get("a"), 2);
    const Vec3 b = VecFromNode(s, key + ".b", tables_segments[i]->get("b"), 2);
    model->segments.push_back(particles::SegmentObstacle{{a[0], a[1]}, {b[0], b[1]}});
  }
}

// [room] width, height, door_width: the crowd room of examples/crowd.toml (room.h).
std::optional<particles::Room> ReadRoom(Scenario& s, particles::ParticleModel* model) {
  if (!s.Has("room")) {
    s.GetNode("room");
    return std::nullopt;
  }
  particles::Room room;
  room.width = s.RequireDouble("room.width");
  room.height = s.RequireDouble("room.height");
  room.door_width = s.RequireDouble("room.door_width");
  try {
    particles::AddRoom(room, model);  // its messages name the field ("room.width must be > 0")
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", s.path(), e.what()));
  }
  return room;
}

std::vector<double> ReadPositions(Scenario& s, const std::string& key, int k, int n) {
  const toml::node* node = s.GetNode(key);
  const toml::array* rows = node ? node->as_array() : nullptr;
  if (rows == nullptr || static_cast<int>(rows->size()) != n) {
    s.Fail(key, fmt::format("expected an array of {} positions (problem.count)", n));
  }
  std::vector<double> x(static_cast<std::size_t>(k) * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Vec3 p = VecFromNode(s, fmt::format("{}[{}]", key, i), &(*rows)[static_cast<std::size_t>(i)], k);
    for (int a = 0; a < k; ++a) x[static_cast<std::size_t>(k * i + a)] = p[static_cast<std::size_t>(a)];
  }
  return x;
}

void WriteFramesCsv(const std::filesystem::path& path, int k, const std::vector<double>& radius,
                    const std::vector<std::pair<double, std::vector<double>>>& frames) {
  std::ofstream f(path);
  f << "t,i,x,y,r\n";
  for (const auto& [t, x] : frames) {
    for (std::size_t i = 0; i < radius.size(); ++i) {
      f << fmt::format("{:.9g},{},{:.9g},{:.9g},{:.9g}\n", t, i, x[static_cast<std::size_t>(k) * i],
                       x[static_cast<std::size_t>(k) * i + 1], radius[i]);
    }
  }
}


// [domain] lo, hi, periodic, box_walls.
void ReadDomain(Scenario& s, particles::ParticleModel* model) {
  const int k = model->dimension;
  const Vec3 lo = ReadVec(s, "domain.lo", k, {0.0, 0.0, 0.0});
  const Vec3 hi = ReadVec(s, "domain.hi", k, {1.0, 1.0, 1.0});
  for (int a = 0; a < k; ++a) {
    if (!(hi[static_cast<std::size_t>(a)] > lo[static_cast<std::size_t>(a)])) {
      s.Fail("domain.hi", fmt::format("must exceed domain.lo on axis {}", a));
    }
  }
  model->domain_lo = lo;
  model->domain_hi = hi;
  if (s.Has("domain.periodic")) {
    const toml::array* arr = s.GetNode("domain.periodic")->as_array();
    if (arr == nullptr || static_cast<int>(arr->size()) != k) {
      s.Fail("domain.periodic", fmt::format("expected {} booleans", k));
    }
    for (int a = 0; a < k; ++a) {
      const auto b = (*arr)[static_cast<std::size_t>(a)].value<bool>();
      if (!b) s.Fail("domain.periodic", "entries must be true or false");
      model->periodic[static_cast<std::size_t>(a)] = *b;
    }
  }
  // Walls on the box faces of the non-periodic axes.
  if (s.GetBool("domain.box_walls", false)) model->AddBoxWalls(lo, hi);
}

// [problem] count, radius or radius_min/max, mobility; [domain]; obstacles; [room].
particles::ParticleModel ReadModel(Scenario& s, int k, int n, std::uint64_t seed) {
  particles::ParticleModel model;
  model.dimension = k;
  // Radii: one value, or uniform in [radius_min, radius_max] (polydisperse, seeded).
  if (s.Has("problem.radius_min") || s.Has("problem.radius_max")) {
    const double rmin =
        s.RequirePositive("problem.radius_min", s.RequireDouble("problem.radius_min"));
    const double rmax = s.RequireDouble("problem.radius_max");
    if (!(rmax >= rmin)) s.Fail("problem.radius_max", "must be ≥ problem.radius_min");
    SplitMix64 rng(seed ^ 0x5DEECE66DULL);
    model.radius.resize(static_cast<std::size_t>(n));
    for (double& r : model.radius) r = rmin + (rmax - rmin) * rng.Uniform01();
  } else {
    const double r = s.RequirePositive("problem.radius", s.RequireDouble("problem.radius"));
    model.radius.assign(static_cast<std::size_t>(n), r);
  }
  const double mobility =
      s.RequirePositive("problem.mobility", s.GetDouble("problem.mobility", 1.0));
  if (mobility != 1.0) model.mobility.assign(static_cast<std::size_t>(n), mobility);
  ReadDomain(s, &model);
  ReadObstacles(s, &model);
  return model;
}

// [forces]; with a room, the walk to its door.
particles::Forces ReadForces(Scenario& s, int k, const std::optional<particles::Room>& room) {
  particles::Forces forces;
  if (s.Has("forces.trap_gamma")) {
    forces.trap = particles::HarmonicTrap{s.GetDouble("forces.trap_gamma", 0.0),
                                          ReadVec(s, "forces.trap_center", k, {0.0, 0.0, 0.0})};
  } else {
    ReadVec(s, "forces.trap_center", k, {0.0, 0.0, 0.0});
  }
  forces.constant_force = ReadVec(s, "forces.constant", k, {0.0, 0.0, 0.0});
  if (s.Has("forces.propulsion_speed") || room) {
    const double speed = s.GetDouble("forces.propulsion_speed", 1.0);
    if (room) {
      forces.propulsion = room->WalkToTheDoor(speed);
    } else {
      particles::SelfPropulsion p;
      p.speed = speed;
      p.target = ReadVec(s, "forces.target", k, {0.0, 0.0, 0.0});
      if (s.Has("forces.target_end")) p.target_end = ReadVec(s, "forces.target_end", k, {});
      forces.propulsion = p;
    }
  }
  if (s.Has("forces.attraction_stiffness")) {
    forces.attraction = particles::PairAttraction{s.GetDouble("forces.attraction_stiffness", 0.0),
                                                  s.GetDouble("forces.attraction_range", 0.0)};
  }
  forces.diffusion = s.GetDouble("forces.diffusion", 0.0);
  WithKey(s, "forces", [&] { forces.Validate(); });
  return forces;
}

// [solver].
particles::EngineOptions ReadEngineOptions(Scenario& s, std::uint64_t seed,
                                           std::int64_t memory_limit) {
  particles::EngineOptions options;
  options.h = s.RequirePositive("solver.h", s.RequireDouble("solver.h"));
  options.seed = seed;
  if (s.Has("solver.order")) {
    options.order = WithKey(s, "solver.order", [&] {
      return particles::ParseSweepOrder(s.GetString("solver.order", ""));
    });
  }
  options.threads = static_cast<int>(s.GetInt("solver.threads", 0));
  options.sweeps = static_cast<int>(s.GetInt("solver.sweeps", 1));
  options.skin_factor = s.GetDouble("solver.skin_factor", options.skin_factor);
  options.block_cells = static_cast<int>(s.GetInt("solver.block_cells", 0));
  options.memory_limit_bytes = memory_limit;
  const std::string method = s.GetString("solver.method", "pbd");
  if (method != "pbd") s.Fail("solver.method", "the particle engine runs pbd");
  WithKey(s, "solver", [&] { options.Validate(); });
  return options;
}

// [initial]: given positions or random sequential addition, then optionally FixOverlaps.
std::vector<double> ReadInitialState(Scenario& s, const particles::ParticleModel& model,
                                     std::uint64_t seed, bool fix, int* fix_sweeps) {
  const int k = model.dimension;
  std::vector<double> x0;
  if (s.Has("initial.positions")) {
    x0 = ReadPositions(s, "initial.positions", k, model.count());
  } else {
    const Vec3 lo = ReadVec(s, "initial.lo", k, model.domain_lo);
    const Vec3 hi = ReadVec(s, "initial.hi", k, model.domain_hi);
    x0 = WithKey(s, "initial",
                 [&] { return particles::RandomSequentialAddition(model, lo, hi, seed); });
  }
  *fix_sweeps = fix ? WithKey(s, "initial", [&] { return particles::FixOverlaps(model, x0); }) : 0;
  return x0;
}

// [output].
struct OutputSettings {
  std::int64_t stride = 1;           // a trajectory frame every stride steps (and the last)
  bool hdf5 = true;
  bool vtu = true;
  bool snapshots = true;             // snapshots.png (2D)
  std::vector<double> snapshot_times;  // empty: the first and the last frame
};

OutputSettings ReadOutputSettings(Scenario& s, int k, int n, std::int64_t steps, double T) {
  OutputSettings o;
  const std::int64_t stride = s.GetInt("output.stride", 0);
  if (stride < 0) s.Fail("output.stride", "must be ≥ 0");
  o.stride = stride > 0 ? stride : std::max<std::int64_t>(1, steps / 100);
  o.hdf5 = s.GetBool("output.hdf5", true);
  o.vtu = s.GetBool("output.vtu", n <= 100000);
  o.snapshots = s.GetBool("output.snapshots", k == 2 && n <= 200000) && k == 2;
  o.snapshot_times = s.GetDoubleArray("output.snapshot_times", {});
  if (o.snapshot_times.size() > 4) s.Fail("output.snapshot_times", "at most four times");
  for (double t : o.snapshot_times) {
    if (t < 0.0 || t > T) s.Fail("output.snapshot_times", fmt::format("{} is outside [0, T]", t));
  }
  return o;
}

// What the run writes as it goes: trajectory frames, snapshot frames, the evacuation series.
class RunRecorder {
 public:
  RunRecorder(OutputDir& out, const OutputSettings& settings, const particles::ParticleModel& model,
              const std::optional<particles::Room>& room, double h, std::int64_t steps)
      : settings_(settings),
        model_(model),
        h_(h),
        steps_(steps),
        ids_(model.radius.size()),
        x_(static_cast<std::size_t>(model.dimension) * model.radius.size()) {
    std::iota(ids_.begin(), ids_.end(), 0);
    if (settings.hdf5) {
      out.Stage("trajectory.xdmf");
      hdf5_ = io::MakeHdf5Writer(out.Stage("trajectory.h5"));
    }
    if (settings.vtu) {
      const std::filesystem::path dir = out.Stage("vtu");
      std::filesystem::create_directories(dir);
      vtu_ = io::MakeVtuSeriesWriter(dir, "frame");
    }
    if (room) evacuation_.emplace(*room, model.count());
  }

  // The engine's observer: positions are copied to id order only for a frame or a snapshot.
  void Observe(const particles::Engine& engine) {
    const std::int64_t step = engine.step();
    const double t = engine.time();
    if (evacuation_) {
      const particles::StoredPositions stored = engine.Stored();
      evacuation_csv_ +=
          fmt::format("{:.9g},{}\n", t, evacuation_->Update(stored.ids, stored.positions));
    }
    const bool frame = step % settings_.stride == 0 || step == steps_;
    const bool snapshot = step == 0 ? settings_.snapshot_times.empty() || IsSnapshotTime(t)
                                    : IsSnapshotTime(t);
    if (frame || snapshot) {
      engine.CopyPositions(x_);
      if (frame) WriteFrame(step, t, x_);
      if (snapshot) snapshots_.emplace_back(t, x_);
    }
    last_step_ = step;
  }

  // After the run: the last good frame after a failure, the final snapshot, writers closed.
  void Finish(bool ok, double t, std::span<const double> x) {
    if (!ok && last_step_ % settings_.stride != 0) WriteFrame(last_step_, t, x);
    if (hdf5_) hdf5_->Close();
    if (vtu_) vtu_->Close();
    if (settings_.snapshot_times.empty()) {
      snapshots_.emplace_back(t, std::vector<double>(x.begin(), x.end()));
    }
  }

  const std::optional<particles::EvacuationCount>& evacuation() const { return evacuation_; }
  const std::string& evacuation_csv() const { return evacuation_csv_; }
  const std::vector<std::pair<double, std::vector<double>>>& snapshots() const {
    return snapshots_;
  }
  bool hdf5() const { return hdf5_ != nullptr; }
  bool vtu() const { return vtu_ != nullptr; }

 private:
  bool IsSnapshotTime(double t) const {
    for (double ts : settings_.snapshot_times) {
      if (std::abs(t - ts) <= 0.5 * h_) return true;
    }
    return false;
  }
  void WriteFrame(std::int64_t step, double t, std::span<const double> x) {
    const io::ParticleFrame frame{step, t, model_.dimension, x.data(), ids_.data(),
                                  model_.radius.data(), model_.count()};
    if (hdf5_) hdf5_->Write(frame);
    if (vtu_) vtu_->Write(frame);
  }

  const OutputSettings& settings_;
  const particles::ParticleModel& model_;
  double h_;
  std::int64_t steps_;
  std::vector<std::int64_t> ids_;
  std::unique_ptr<io::TrajectoryWriter> hdf5_, vtu_;
  std::optional<particles::EvacuationCount> evacuation_;
  std::string evacuation_csv_ = "t,out\n";
  std::vector<std::pair<double, std::vector<double>>> snapshots_;
  std::int64_t last_step_ = 0;
  std::vector<double> x_;  // positions in id order for frames and snapshots
};

// summary.json: the engine's summary (counters, *_seconds, settings) and the run's context.
nlohmann::json RunSummaryJson(const particles::Engine& engine,
                              const particles::EngineSummary& summary, const Scenario& s,
                              int fix_sweeps, std::span<const double> x) {
  nlohmann::json j = summary.ToJson();
  j["method"] = "pbd";
  j["engine"] = "particles";
  j["h"] = summary.settings.h;
  j["particles"] = engine.count();
  j["dimension"] = engine.dimension();
  j["threads"] = engine.threads();
  j["sweep_order"] = particles::SweepOrderName(summary.settings.order);
  j["max_violation"] = summary.stats.max_overlap;
  j["fix_overlaps_sweeps"] = fix_sweeps;
  j["scenario_file"] = s.path();
  j["positions_hash"] = HashDoublesHex(x);  // final positions, id order (FNV-1a of the bits)
  return j;
}

// The summary, the evacuation series and the figures into the output directory.
void WriteRunOutputs(OutputDir& out, const RunRecorder& recorder, nlohmann::json j,
                     const OutputSettings& settings, const particles::ParticleModel& model) {
  const auto& evacuation = recorder.evacuation();
  if (evacuation) {
    j["evacuated"] = evacuation->out();
    out.WriteText("evacuation.csv", recorder.evacuation_csv());
    RunPlotScript("plot_particles.py", {"--series", out.Stage("evacuation.png").string(),
                                        out.StagedPath("evacuation.csv").string(), "time",
                                        "people out"});
  }
  out.WriteText("summary.json", j.dump(2) + "\n");
  if (settings.snapshots) {
    const std::filesystem::path csv = out.StagedPath(".snapshots.csv");
    WriteFramesCsv(csv, model.dimension, model.radius, recorder.snapshots());
    RunPlotScript("plot_particles.py", {out.Stage("snapshots.png").string(), csv.string()});
    std::filesystem::remove(csv);
  }
}

}  // namespace

int RunParticleScenario(Scenario& s, const ParticleRunFlags& flags) {
  const std::int64_t dim = s.GetInt("problem.dimension", 2);
  if (dim != 2 && dim != 3) {
    s.Fail("problem.dimension", fmt::format("must be 2 or 3 (got {})", dim));
  }
  const int k = static_cast<int>(dim);
  const std::int64_t count = s.RequireInt("problem.count");
  if (count < 1) s.Fail("problem.count", fmt::format("must be ≥ 1 (got {})", count));
  const std::int64_t memory_limit = s.GetInt("solver.memory_limit", 0);
  if (memory_limit < 0) s.Fail("solver.memory_limit", "must be ≥ 0 (bytes; 0 = physical memory)");
  // Before anything of size N is allocated.
  WithKey(s, "problem.count", [&] { particles::CheckParticleMemory(k, count, memory_limit); });
  if (count > std::numeric_limits<int>::max()) s.Fail("problem.count", "too many particles");
  const int n = static_cast<int>(count);
  const auto seed = static_cast<std::uint64_t>(s.GetInt("problem.seed", 1));
  const double T = s.RequirePositive("problem.T", s.RequireDouble("problem.T"));

  particles::ParticleModel model = ReadModel(s, k, n, seed);
  const std::optional<particles::Room> room = ReadRoom(s, &model);
  WithKey(s, "problem", [&] { model.Validate(); });
  const particles::Forces forces = ReadForces(s, k, room);
  const particles::EngineOptions options = ReadEngineOptions(s, seed, memory_limit);
  const std::int64_t steps = WithKey(s, "solver.h", [&] { return StepCount(T, options.h); });
  const bool fix = flags.fix_overlaps || s.GetBool("problem.fix_overlaps", false);
  int fix_sweeps = 0;
  const std::vector<double> x0 = ReadInitialState(s, model, seed, fix, &fix_sweeps);
  const OutputSettings settings = ReadOutputSettings(s, k, n, steps, T);
  s.CheckAllKeysUsed();

  particles::Engine engine =
      WithKey(s, "initial", [&] { return particles::Engine(model, forces, options, x0); });
  OutputDir out(flags.out);
  RunRecorder recorder(out, settings, model, room, options.h, steps);
  ProgressBar progress("run", steps);
  const particles::EngineSummary summary =
      engine.Run(T, [&](const particles::Engine& e) {
        recorder.Observe(e);
        progress.Update(e.step());
      });
  progress.Finish();
  const std::vector<double> x = engine.Positions();
  recorder.Finish(summary.ok(), engine.time(), x);
  WriteRunOutputs(out, recorder, RunSummaryJson(engine, summary, s, fix_sweeps, x), settings,
                  model);
  out.Commit();
  std::printf("%s\n", summary.BriefReport().c_str());
  if (recorder.evacuation()) {
    std::printf("people out at t = %g: %d of %d\n", engine.time(), recorder.evacuation()->out(), n);
  }
  std::printf("wrote %s/summary.json%s%s%s\n", out.dir().c_str(),
              recorder.hdf5() ? ", trajectory.h5 + .xdmf" : "",
              recorder.vtu() ? ", vtu/frame.pvd" : "", settings.snapshots ? ", snapshots.png" : "");
  if (!summary.ok()) {
    std::fprintf(stderr, "moreau: numerical failure: %s\n", summary.message.c_str());
    return 3;
  }
  return 0;
}

}  // namespace moreau::cli
