// Convergence and precision–work studies: error against an exact or reference solution over a set
// of step sizes and methods, the observed order, and errors at equal work.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "moreau/pbd/particle_constraints.h"
#include "moreau/pbd/stepper.h"

namespace moreau::pbd {

// A method with its parameter, as named on the command line: "pbd", "pngs", "pgs",
// "penalty:GAMMA" (plain "penalty" uses the scenario's solver.penalty).
struct MethodSpec {
  Method method = Method::kPBD;
  double penalty = 0.0;  // 0: take StepperOptions::penalty
  std::string label;     // "pbd", "penalty:100", …
};
// Throws InputError for an unknown method or a bad γ.
MethodSpec ParseMethodSpec(const std::string& text);

// States sampled every dt from t = 0, linearly interpolated in between.
class SampledTrajectory {
 public:
  SampledTrajectory() = default;
  explicit SampledTrajectory(double dt) : dt_(dt) {}
  void Append(ConstVectorRef x) { states_.emplace_back(x); }
  double dt() const { return dt_; }
  double end_time() const { return dt_ * static_cast<double>(states_.size() - 1); }
  std::size_t size() const { return states_.size(); }
  const Vector& state(std::size_t k) const { return states_[k]; }
  // x(t); exact on the samples. t must lie in [0, end_time()] (to within 1e−9 dt).
  Vector At(double t) const;

 private:
  double dt_ = 0.0;
  std::vector<Vector> states_;
};

// The constraint model of a study: immutable and shared by all its runs; each run makes its own
// workspace from it (a Constraints object holds per-run state: neighbour lists, scratch).
class ConstraintModel {
 public:
  virtual ~ConstraintModel() = default;
  virtual std::unique_ptr<Constraints> MakeWorkspace() const = 0;
};

// A particle system: one shared particle model; each workspace is a ParticleConstraints with its
// own neighbour list. Throws InputError for a null model.
class ParticleSystemModel final : public ConstraintModel {
 public:
  explicit ParticleSystemModel(std::shared_ptr<const particles::ParticleModel> model,
                               ParticleConstraintsOptions options = {});
  const particles::ParticleModel& model() const { return *model_; }
  std::unique_ptr<Constraints> MakeWorkspace() const override;

 private:
  std::shared_ptr<const particles::ParticleModel> model_;
  ParticleConstraintsOptions options_;
};

// A case whose sets are built by `Case::MakeConstraints() const` (SlidingCase): the case is the
// model, each workspace a fresh set list.
template <typename Case>
class CaseConstraintModel final : public ConstraintModel {
 public:
  explicit CaseConstraintModel(Case c) : case_(std::move(c)) {}
  std::unique_ptr<Constraints> MakeWorkspace() const override { return case_.MakeConstraints(); }

 private:
  Case case_;
};

// Everything a study needs about a problem.
struct StudyProblem {
  std::shared_ptr<const ConstraintModel> constraints;
  std::shared_ptr<const Drift> drift;
  Vector x0;
  double T = 0.0;
  // The exact or reference solution x(t).
  std::function<Vector(double)> solution;
};

// A reference solution by one run of `options` (normally PNGS with tight tolerances and small h),
// sampled every sample_dt (a whole multiple of options.h). Throws NumericalError if it fails.
SampledTrajectory ComputeReference(const StudyProblem& problem, const StepperOptions& options,
                                   double sample_dt);

struct StudyRow {
  std::string label;
  Method method = Method::kPBD;
  double h = 0.0;
  double error = 0.0;  // max_k ‖x_k − x(t_k)‖ over the time grid; +inf when the run failed
  std::int64_t constraint_evaluations = 0;
  std::int64_t sweeps = 0;
  double max_violation = 0.0;
  double total_seconds = 0.0;
  // kCompleted, or kNonFinite when the run or its error stopped being finite.
  Termination termination = Termination::kCompleted;
  std::string message;

  bool ok() const { return IsSuccess(termination); }
  // SummaryJson + h, error, constraint_evaluations, sweeps, max_violation (non-finite as null).
  nlohmann::json ToJson() const;
};

// One run of a study: method `spec` at step h (tolerances and γ from `base`), its error against
// problem.solution on the time grid. Thread-safe for one problem (each run has its own
// constraint workspace).
StudyRow RunStudyPoint(const StudyProblem& problem, const MethodSpec& spec, double h,
                       const StepperOptions& base);

// Runs every method at every h (from `base` for tolerances and γ). progress, if set, is called
// after each run with (runs done, runs in all).
std::vector<StudyRow> RunStudy(const StudyProblem& problem, const std::vector<MethodSpec>& methods,
                               const std::vector<double>& hs, const StepperOptions& base,
                               const std::function<void(int, int)>& progress = {});

// The least-squares slope of log(error) against log(h) through the given points (finite, positive
// errors only); NaN with fewer than two such points.
double ObservedOrder(const std::vector<double>& h, const std::vector<double>& error);

// The error of one method's precision–work curve at `budget` constraint evaluations, by linear
// interpolation of log(error) in log(evaluations); NaN outside the range the rows cover.
double ErrorAtBudget(const std::vector<StudyRow>& rows, const std::string& label, double budget);

}  // namespace moreau::pbd
