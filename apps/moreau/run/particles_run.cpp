#include "run/particles_run.h"

#include <cmath>
#include <filesystem>
#include <memory>
#include <numeric>
#include <span>
#include <tuple>

#include <fmt/format.h>

#include "field_table.h"
#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "moreau/io/text_trajectory.h"
#include "moreau/io/trajectory.h"
#include "moreau/particles/room.h"
#include "progress.h"
#include "run/scene_geometry.h"
#include "signals.h"

namespace moreau::cli {
namespace {

// "id,exit": who left through which exit, ascending ids.
std::string ExitsCsv(const particles::EvacuationCount& count) {
  std::string csv = "id,exit\n";
  const std::vector<int> ids = count.OutIds();
  const std::vector<int> exits = count.OutExits();
  for (std::size_t k = 0; k < ids.size(); ++k) csv += fmt::format("{},{}\n", ids[k], exits[k]);
  return csv;
}

// What the run writes as it goes: trajectory frames, snapshot frames, the evacuation series.
class RunRecorder {
 public:
  RunRecorder(OutputDir& out, const ParticleScenario& scenario, const particles::Engine& engine,
              std::int64_t steps)
      : output_(scenario.output),
        stride_(output_.stride > 0 ? output_.stride : std::max<std::int64_t>(1, steps / 100)),
        model_(engine.model()),
        h_(engine.options().h),
        steps_(steps),
        ids_(model_.radius.size()),
        x_(static_cast<std::size_t>(model_.dimension) * model_.radius.size()) {
    std::iota(ids_.begin(), ids_.end(), 0);
    if (output_.hdf5) {
      out.Stage("trajectory.xdmf");
      hdf5_ = io::MakeHdf5Writer(out.Stage("trajectory.h5"), output_.trajectory);
    }
    if (output_.trajectory_txt) {
      io::TextTrajectoryOptions text;
      text.frame_rate = 1.0 / (h_ * static_cast<double>(stride_));
      text.steps_per_frame = stride_;
      text.comments = {fmt::format("moreau run: h = {:g} s, a frame every {} steps", h_, stride_)};
      txt_ = io::MakeTextTrajectoryWriter(out.Stage("trajectory.txt"), text);
    }
    if (output_.vtu) {
      const std::filesystem::path dir = out.Stage("vtu");
      std::filesystem::create_directories(dir);
      vtu_ = io::MakeVtuSeriesWriter(dir, "frame");
    }
    geometry_ = WriteSceneGeometry(model_, scenario, out);
    if (scenario.room) evacuation_.emplace(*scenario.room, model_.count());
    if (scenario.geometry) evacuation_.emplace(*scenario.geometry, model_.count());
  }

  // The engine's observer: positions are copied to id order only for a frame or a snapshot.
  void Observe(const particles::Engine& engine) {
    const std::int64_t step = engine.step();
    const double t = engine.time();
    if (evacuation_) {
      const particles::StoredPositions stored = engine.Stored();
      evacuation_csv_ += fmt::format(
          "{:.9g},{}\n", t, evacuation_->Update(stored.ids, stored.positions, engine.threads()));
    }
    const bool frame = step % stride_ == 0 || step == steps_;
    const bool snapshot =
        step == 0 ? output_.snapshot_times.empty() || IsSnapshotTime(t) : IsSnapshotTime(t);
    if (frame || snapshot) {
      engine.CopyPositions(x_);
      if (frame) WriteFrame(step, t, x_);
      if (snapshot) snapshots_.emplace_back(t, x_);
    }
    last_step_ = step;
  }

  // Checkpoints: frames are kept from now on; State() holds them, the snapshots and the last
  // step seen; Resume writes a state's frames and takes its snapshots (a resumed run).
  void KeepFrames() { keep_frames_ = true; }
  nlohmann::json State() const {
    nlohmann::json j = {{"frames", kept_}, {"snapshots", snapshots_}, {"last_step", last_step_}};
    if (evacuation_) {
      j["evacuation"] = {{"out", evacuation_->OutIds()},
                         {"exits", evacuation_->OutExits()},
                         {"csv", evacuation_csv_}};
    }
    return j;
  }
  void Resume(const nlohmann::json& state) {
    try {
      for (const auto& f : state.at("frames")) {
        const std::vector<double> x = f.at(2).get<std::vector<double>>();
        if (x.size() != x_.size()) throw InputError("checkpoint: a frame does not fit the run");
        WriteFrame(f.at(0).get<std::int64_t>(), f.at(1).get<double>(), x);
      }
      state.at("snapshots").get_to(snapshots_);
      state.at("last_step").get_to(last_step_);
      if (evacuation_) {
        evacuation_->RestoreOut(state.at("evacuation").at("out").get<std::vector<int>>(),
                                state.at("evacuation").value("exits", std::vector<int>{}));
        state.at("evacuation").at("csv").get_to(evacuation_csv_);
      }
    } catch (const nlohmann::json::exception&) {
      throw InputError("checkpoint: the run's frames, snapshots or evacuation are malformed");
    }
  }

  // After the run: the last good frame after a failure, the final snapshot, writers closed.
  ParticleRunResult Finish(const particles::EngineSummary& summary, double t,
                           std::vector<double> x) {
    if (!summary.ok() && last_step_ % stride_ != 0) WriteFrame(last_step_, t, x);
    if (hdf5_) hdf5_->Close();
    if (vtu_) vtu_->Close();
    if (txt_) txt_->Close();
    if (output_.snapshot_times.empty()) snapshots_.emplace_back(t, x);
    ParticleRunResult result{
        summary,         std::move(x), std::nullopt,   "", std::move(snapshots_), hdf5_ != nullptr,
        vtu_ != nullptr, geometry_,    txt_ != nullptr, {}};
    if (evacuation_) {
      result.evacuated = evacuation_->out();
      result.evacuation_csv = std::move(evacuation_csv_);
      if (evacuation_->exits() > 1) result.exits_csv = ExitsCsv(*evacuation_);
    }
    return result;
  }

 private:
  bool IsSnapshotTime(double t) const {
    for (double ts : output_.snapshot_times) {
      if (std::abs(t - ts) <= 0.5 * h_) return true;
    }
    return false;
  }
  void WriteFrame(std::int64_t step, double t, std::span<const double> x) {
    if (keep_frames_) kept_.push_back({step, t, std::vector<double>(x.begin(), x.end())});
    const io::ParticleFrame frame{
        step, t, model_.dimension, x.data(), ids_.data(), model_.radius.data(), model_.count(), {}};
    if (hdf5_) hdf5_->Write(frame);
    if (vtu_) vtu_->Write(frame);
    if (txt_) txt_->Write(frame);  // the frames on the stride only
  }

  const ParticleOutputSettings& output_;
  std::int64_t stride_;  // a frame every stride steps (and the last)
  const particles::ParticleModel& model_;
  double h_;
  std::int64_t steps_;
  std::vector<std::int64_t> ids_;
  std::unique_ptr<io::TrajectoryWriter> hdf5_, vtu_, txt_;
  bool geometry_ = false;  // geometry.vtp written
  std::optional<particles::EvacuationCount> evacuation_;
  std::string evacuation_csv_ = "t,out\n";
  std::vector<std::pair<double, std::vector<double>>> snapshots_;
  std::int64_t last_step_ = 0;
  std::vector<double> x_;  // positions in id order for frames and snapshots
  bool keep_frames_ = false;
  std::vector<std::tuple<std::int64_t, double, std::vector<double>>> kept_;  // (step, t, x)
};

}  // namespace

std::vector<double> InitialPositions(const ParticleScenario& scenario,
                                     const particles::ParticleModel& model, const Scenario& file) {
  if (scenario.positions) return *scenario.positions;
  std::vector<double> x0;
  WithKey(file, "initial", [&] {
    x0 = particles::RandomSequentialAddition(model, scenario.initial_lo.value_or(model.domain_lo),
                                             scenario.initial_hi.value_or(model.domain_hi),
                                             static_cast<std::uint64_t>(scenario.seed));
  });
  return x0;
}

ParticleSetup SetUpParticleRun(const ParticleScenario& scenario, const Scenario& file) {
  particles::ParticleModel model = scenario.MakeModel();
  WithKey(file, "problem", [&] { model.Validate(); });
  std::vector<double> x0 = InitialPositions(scenario, model, file);
  int fix_sweeps = 0;
  if (scenario.fix_overlaps) {
    // A start that cannot be projected to a feasible one is bad input, not a failed run.
    const char* key = scenario.positions ? "initial.positions" : "initial";
    try {
      WithKey(file, key, [&] { fix_sweeps = particles::FixOverlaps(model, x0); });
    } catch (const NumericalError& e) {
      file.Fail(key, fmt::format("cannot be made feasible (--fix-overlaps): {}", e.what()));
    }
  }
  std::optional<particles::Engine> engine;
  WithKey(file, "initial", [&] {
    engine.emplace(std::move(model), scenario.MakeForces(), scenario.MakeEngineOptions(), x0);
  });
  std::vector<double> start = engine->Positions();
  return {std::move(*engine), std::move(start), fix_sweeps,
          StepCount(scenario.T, scenario.solver.h)};
}

ParticleRunResult RunParticles(const ParticleScenario& scenario, ParticleSetup& setup,
                               OutputDir& out, const CheckpointPlan& checkpoints) {
  particles::Engine& engine = setup.engine;
  RunRecorder recorder(out, scenario, engine, setup.steps);
  if (checkpoints.every > 0 || checkpoints.resumed) recorder.KeepFrames();
  if (checkpoints.resumed) recorder.Resume(*checkpoints.resumed);
  ProgressBar progress("run", setup.steps);
  const StopScope stop_on_signal;  // SIGINT/SIGTERM: stop after the current step
  // Returns false (the run stops after this step) once a signal asked to stop, unless the run
  // is complete.
  const auto observe = [&](const particles::Engine& e) {
    recorder.Observe(e);
    progress.Update(e.step());
    const std::int64_t step = e.step();
    if (checkpoints.every > 0 && step > 0 && step < setup.steps && step % checkpoints.every == 0) {
      WriteRunCheckpoint(checkpoints, e, recorder.State());
    }
    return step >= setup.steps || !StopRequested();
  };
  particles::EngineSummary summary =
      checkpoints.resumed ? engine.Continue(scenario.T, observe) : engine.Run(scenario.T, observe);
  if (summary.termination == Termination::kInterrupted) {
    summary = InterruptedSummary(std::move(summary), engine.step(), engine.time());
  }
  progress.Finish();
  return recorder.Finish(summary, engine.time(), engine.Positions());
}

}  // namespace moreau::cli
