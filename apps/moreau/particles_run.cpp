#include "particles_run.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>

#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "moreau/io/trajectory.h"
#include "moreau/particles/engine.h"
#include "moreau/pbd/cases.h"
#include "moreau/pbd/stepper.h"
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

// The crowd room of examples/crowd.toml: [room] width, height, door_width → segments for the
// walls, with a door centred on the right wall (x = width).
struct Room {
  double width = 0.0;
  double height = 0.0;
  double door_lo = 0.0;
  double door_hi = 0.0;
};

std::optional<Room> ReadRoom(Scenario& s, particles::ParticleModel* model) {
  if (!s.Has("room")) {
    s.GetNode("room");
    return std::nullopt;
  }
  if (model->dimension != 2) s.Fail("room", "a room needs dimension 2");
  Room room;
  room.width = s.RequirePositive("room.width", s.RequireDouble("room.width"));
  room.height = s.RequirePositive("room.height", s.RequireDouble("room.height"));
  const double door = s.RequirePositive("room.door_width", s.RequireDouble("room.door_width"));
  if (door >= room.height) s.Fail("room.door_width", "must be smaller than the room height");
  room.door_lo = 0.5 * (room.height - door);
  room.door_hi = 0.5 * (room.height + door);
  const double W = room.width, H = room.height;
  model->segments.push_back({{0.0, 0.0}, {W, 0.0}});
  model->segments.push_back({{0.0, H}, {W, H}});
  model->segments.push_back({{0.0, 0.0}, {0.0, H}});
  model->segments.push_back({{W, 0.0}, {W, room.door_lo}});
  model->segments.push_back({{W, room.door_hi}, {W, H}});
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

}  // namespace

int RunParticleScenario(Scenario& s, const ParticleRunFlags& flags) {
  namespace fs = std::filesystem;
  particles::ParticleModel model;
  const std::int64_t dim = s.GetInt("problem.dimension", 2);
  if (dim != 2 && dim != 3) s.Fail("problem.dimension", fmt::format("must be 2 or 3 (got {})", dim));
  model.dimension = static_cast<int>(dim);
  const int k = model.dimension;
  const std::int64_t count = s.RequireInt("problem.count");
  if (count < 1) s.Fail("problem.count", fmt::format("must be ≥ 1 (got {})", count));
  const std::int64_t memory_limit = s.GetInt("solver.memory_limit", 0);
  if (memory_limit < 0) s.Fail("solver.memory_limit", "must be ≥ 0 (bytes; 0 = physical memory)");
  // Before anything of size N is allocated.
  WithKey(s, "problem.count", [&] { particles::CheckParticleMemory(k, count, memory_limit); });
  if (count > std::numeric_limits<int>::max()) s.Fail("problem.count", "too many particles");
  const int n = static_cast<int>(count);
  const std::uint64_t seed = static_cast<std::uint64_t>(s.GetInt("problem.seed", 1));
  const double T = s.RequirePositive("problem.T", s.RequireDouble("problem.T"));

  // Radii: one value, or uniform in [radius_min, radius_max] (polydisperse, seeded).
  if (s.Has("problem.radius_min") || s.Has("problem.radius_max")) {
    const double rmin = s.RequirePositive("problem.radius_min", s.RequireDouble("problem.radius_min"));
    const double rmax = s.RequireDouble("problem.radius_max");
    if (!(rmax >= rmin)) s.Fail("problem.radius_max", "must be ≥ problem.radius_min");
    SplitMix64 rng(seed ^ 0x5DEECE66DULL);
    model.radius.resize(static_cast<std::size_t>(n));
    for (double& r : model.radius) r = rmin + (rmax - rmin) * rng.Uniform01();
  } else {
    const double r = s.RequirePositive("problem.radius", s.RequireDouble("problem.radius"));
    model.radius.assign(static_cast<std::size_t>(n), r);
  }
  const double mobility = s.RequirePositive("problem.mobility", s.GetDouble("problem.mobility", 1.0));
  if (mobility != 1.0) model.mobility.assign(static_cast<std::size_t>(n), mobility);

  // Domain and boundaries.
  const Vec3 lo = ReadVec(s, "domain.lo", k, {0.0, 0.0, 0.0});
  const Vec3 hi = ReadVec(s, "domain.hi", k, {1.0, 1.0, 1.0});
  for (int a = 0; a < k; ++a) {
    if (!(hi[static_cast<std::size_t>(a)] > lo[static_cast<std::size_t>(a)])) {
      s.Fail("domain.hi", fmt::format("must exceed domain.lo on axis {}", a));
    }
  }
  model.domain_lo = lo;
  model.domain_hi = hi;
  if (s.Has("domain.periodic")) {
    const toml::node* node = s.GetNode("domain.periodic");
    const toml::array* arr = node->as_array();
    if (arr == nullptr || static_cast<int>(arr->size()) != k) {
      s.Fail("domain.periodic", fmt::format("expected {} booleans", k));
    }
    for (int a = 0; a < k; ++a) {
      const auto b = (*arr)[static_cast<std::size_t>(a)].value<bool>();
      if (!b) s.Fail("domain.periodic", "entries must be true or false");
      model.periodic[static_cast<std::size_t>(a)] = *b;
    }
  }
  if (s.GetBool("domain.box_walls", false)) {
    // Walls on the box faces of the non-periodic axes.
    for (int a = 0; a < k; ++a) {
      if (model.periodic[static_cast<std::size_t>(a)]) continue;
      particles::Wall low, high;
      low.normal = {0.0, 0.0, 0.0};
      high.normal = {0.0, 0.0, 0.0};
      low.normal[static_cast<std::size_t>(a)] = 1.0;
      low.offset = lo[static_cast<std::size_t>(a)];
      high.normal[static_cast<std::size_t>(a)] = -1.0;
      high.offset = -hi[static_cast<std::size_t>(a)];
      model.walls.push_back(low);
      model.walls.push_back(high);
    }
  }
  ReadObstacles(s, &model);
  const std::optional<Room> room = ReadRoom(s, &model);
  WithKey(s, "problem", [&] { model.Validate(); });

  // Forces.
  particles::Forces forces;
  if (s.Has("forces.trap_gamma")) {
    forces.trap = particles::HarmonicTrap{s.GetDouble("forces.trap_gamma", 0.0),
                                          ReadVec(s, "forces.trap_center", k, {0.0, 0.0, 0.0})};
  } else {
    ReadVec(s, "forces.trap_center", k, {0.0, 0.0, 0.0});
  }
  forces.constant_force = ReadVec(s, "forces.constant", k, {0.0, 0.0, 0.0});
  if (s.Has("forces.propulsion_speed") || room) {
    particles::SelfPropulsion p;
    p.speed = s.GetDouble("forces.propulsion_speed", 1.0);
    if (room) {
      // Head for the door; once through it, keep walking away from the room.
      p.target = {room->width, room->door_lo, 0.0};
      p.target_end = Vec3{room->width, room->door_hi, 0.0};
      p.exit_direction = Vec3{1.0, 0.0, 0.0};
    } else {
      p.target = ReadVec(s, "forces.target", k, {0.0, 0.0, 0.0});
      if (s.Has("forces.target_end")) p.target_end = ReadVec(s, "forces.target_end", k, {});
    }
    forces.propulsion = p;
  }
  if (s.Has("forces.attraction_stiffness")) {
    forces.attraction = particles::PairAttraction{s.GetDouble("forces.attraction_stiffness", 0.0),
                                                  s.GetDouble("forces.attraction_range", 0.0)};
  }
  forces.diffusion = s.GetDouble("forces.diffusion", 0.0);
  WithKey(s, "forces", [&] { forces.Validate(); });

  // Solver.
  particles::EngineOptions options;
  options.h = s.RequirePositive("solver.h", s.RequireDouble("solver.h"));
  options.seed = seed;
  if (s.Has("solver.order")) {
    options.order = WithKey(s, "solver.order",
                            [&] { return particles::ParseSweepOrder(s.GetString("solver.order", "")); });
  }
  options.threads = static_cast<int>(s.GetInt("solver.threads", 0));
  options.sweeps = static_cast<int>(s.GetInt("solver.sweeps", 1));
  options.skin_factor = s.GetDouble("solver.skin_factor", options.skin_factor);
  options.block_cells = static_cast<int>(s.GetInt("solver.block_cells", 0));
  options.memory_limit_bytes = memory_limit;
  const std::string method = s.GetString("solver.method", "pbd");
  if (method != "pbd") s.Fail("solver.method", "the particle engine runs pbd");
  WithKey(s, "solver", [&] { options.Validate(); });
  const std::int64_t steps = WithKey(s, "solver.h", [&] { return StepCount(T, options.h); });

  // Initial state.
  std::vector<double> x0;
  const bool fix = flags.fix_overlaps || s.GetBool("problem.fix_overlaps", false);
  if (s.Has("initial.positions")) {
    x0 = ReadPositions(s, "initial.positions", k, n);
  } else {
    Vec3 ilo = ReadVec(s, "initial.lo", k, lo);
    Vec3 ihi = ReadVec(s, "initial.hi", k, hi);
    x0 = WithKey(s, "initial", [&] { return particles::RandomSequentialAddition(model, ilo, ihi, seed); });
  }
  int fix_sweeps = 0;
  if (fix) {
    fix_sweeps = WithKey(s, "initial", [&] { return particles::FixOverlaps(model, x0); });
  }
  const std::int64_t stride_in = s.GetInt("output.stride", 0);
  if (stride_in < 0) s.Fail("output.stride", "must be ≥ 0");
  const std::int64_t stride = stride_in > 0 ? stride_in : std::max<std::int64_t>(1, steps / 100);
  const bool write_hdf5 = s.GetBool("output.hdf5", true);
  const bool write_vtu = s.GetBool("output.vtu", n <= 100000);
  const bool snapshots = s.GetBool("output.snapshots", k == 2 && n <= 200000);
  // Times of the snapshot frames; by default the first and the last frame.
  std::vector<double> snapshot_times = s.GetDoubleArray("output.snapshot_times", {});
  if (snapshot_times.size() > 4) s.Fail("output.snapshot_times", "at most four times");
  for (double t : snapshot_times) {
    if (t < 0.0 || t > T) s.Fail("output.snapshot_times", fmt::format("{} is outside [0, T]", t));
  }
  s.CheckAllKeysUsed();

  particles::Engine engine = WithKey(s, "initial", [&] {
    return particles::Engine(model, forces, options, x0);
  });

  OutputDir out(flags.out);
  std::unique_ptr<io::TrajectoryWriter> hdf5, vtu;
  if (write_hdf5) {
    out.Stage("trajectory.xdmf");
    hdf5 = io::MakeHdf5Writer(out.Stage("trajectory.h5"));
  }
  if (write_vtu) {
    const fs::path dir = out.Stage("vtu");
    fs::create_directories(dir);
    vtu = io::MakeVtuSeriesWriter(dir, "frame");
  }
  std::vector<std::int64_t> ids(static_cast<std::size_t>(n));
  std::iota(ids.begin(), ids.end(), 0);
  std::vector<double> x(static_cast<std::size_t>(k) * static_cast<std::size_t>(n));
  const auto write_frame = [&] {
    engine.CopyPositions(x);
    const io::ParticleFrame frame{engine.step(), engine.time(), k, x.data(), ids.data(),
                                  model.radius.data(), n};
    if (hdf5) hdf5->Write(frame);
    if (vtu) vtu->Write(frame);
  };
  std::vector<std::pair<double, std::vector<double>>> first_last;
  const auto is_snapshot_time = [&](double t) {
    for (double ts : snapshot_times) {
      if (std::abs(t - ts) <= 0.5 * options.h) return true;
    }
    return false;
  };
  engine.CopyPositions(x);
  if (snapshot_times.empty() || is_snapshot_time(0.0)) first_last.emplace_back(0.0, x);
  write_frame();

  std::string evacuation = "t,out\n";
  // A person is out from the first time their centre passes the door line x = width (noise may
  // carry them back over it for a moment; they still count as out).
  std::vector<char> left(room ? static_cast<std::size_t>(n) : 0, 0);
  int outside = 0;
  const auto count_out = [&] {
    for (int i = 0; i < n; ++i) {
      if (!left[static_cast<std::size_t>(i)] && x[static_cast<std::size_t>(k * i)] > room->width) {
        left[static_cast<std::size_t>(i)] = 1;
        ++outside;
      }
    }
    return outside;
  };
  if (room) evacuation += fmt::format("0,{}\n", count_out());

  ProgressBar progress("run", steps);
  bool ok = true;
  std::string failure;  // a NumericalError from the engine
  for (std::int64_t step = 1; step <= steps; ++step) {
    bool stepped = false;
    try {
      stepped = engine.Step();
    } catch (const NumericalError& e) {  // the step could not be completed; the state is the last good one
      failure = e.what();
    }
    if (!stepped) {
      ok = false;
      break;
    }
    if (room) {
      engine.CopyPositions(x);
      evacuation += fmt::format("{:.9g},{}\n", engine.time(), count_out());
    }
    if (step % stride == 0 || step == steps) write_frame();
    if (!snapshot_times.empty() && is_snapshot_time(engine.time())) {
      engine.CopyPositions(x);
      first_last.emplace_back(engine.time(), x);
    }
    progress.Update(step);
  }
  progress.Finish();
  const particles::EngineSummary summary = engine.summary();
  if (!ok && engine.step() % stride != 0) write_frame();  // the last good frame
  if (hdf5) hdf5->Close();
  if (vtu) vtu->Close();
  engine.CopyPositions(x);
  if (snapshot_times.empty()) first_last.emplace_back(engine.time(), x);

  nlohmann::json j;
  const particles::EngineStats& st = summary.stats;
  j["method"] = "pbd";
  j["engine"] = "particles";
  j["h"] = options.h;
  j["steps"] = st.steps;
  j["final_time"] = st.time;
  j["particles"] = n;
  j["dimension"] = k;
  j["threads"] = engine.threads();
  j["sweep_order"] = particles::SweepOrderName(options.order);
  j["constraint_evaluations"] = st.constraint_evaluations;
  j["constraint_sets_paper_count"] = st.constraint_sets;
  j["neighbour_list_rebuilds"] = st.neighbour_builds;
  j["verlet_retries"] = st.verlet_retries;
  j["candidate_pairs"] = st.candidate_pairs;
  j["max_overlap"] = st.max_overlap;
  j["max_violation"] = st.max_overlap;
  j["fix_overlaps_sweeps"] = fix_sweeps;
  j["wall_seconds"] = st.total_seconds;
  j["timings"] = {{"setup", st.setup_seconds},        {"forces", st.force_seconds},
                  {"neighbour_lists", st.neighbour_seconds}, {"sweeps", st.sweep_seconds},
                  {"monitor", st.monitor_seconds},    {"total", st.total_seconds}};
  j["termination"] = !failure.empty() ? "numerical_failure" : summary.ok() ? "completed" : "non_finite";
  if (!failure.empty()) {
    j["message"] = failure + fmt::format("; the state of step {} is kept", engine.step());
  } else if (!summary.ok()) {
    j["message"] = summary.message;
    j["failed_step"] = summary.failed_step;
    j["failed_particle"] = summary.failed_particle;
  }
  j["scenario_file"] = s.path();
  if (room) {
    j["evacuated"] = count_out();
    out.WriteText("evacuation.csv", evacuation);
    RunPlotScript("plot_particles.py", {"--series", out.Stage("evacuation.png").string(),
                                        out.StagedPath("evacuation.csv").string(), "time",
                                        "people out"});
  }
  out.WriteText("summary.json", j.dump(2) + "\n");
  if (snapshots && k == 2) {
    const fs::path csv = out.StagedPath(".snapshots.csv");
    WriteFramesCsv(csv, k, model.radius, first_last);
    RunPlotScript("plot_particles.py", {out.Stage("snapshots.png").string(), csv.string()});
    fs::remove(csv);
  }
  out.Commit();
  std::printf("%s\n", summary.BriefReport().c_str());
  if (room) std::printf("people out at t = %g: %d of %d\n", engine.time(), outside, n);
  std::printf("wrote %s/summary.json%s%s%s\n", out.dir().c_str(),
              hdf5 ? ", trajectory.h5 + .xdmf" : "", vtu ? ", vtu/frame.pvd" : "",
              snapshots && k == 2 ? ", snapshots.png" : "");
  if (!ok) {
    std::fprintf(stderr, "moreau: numerical failure: %s\n",
                 failure.empty() ? summary.message.c_str() : failure.c_str());
    return 3;
  }
  return 0;
}

}  // namespace moreau::cli
