// Time steppers for x' ∈ f(x) − N(S, x), S = S_1 ∩ … ∩ S_m, behind one interface.
//
//   PBD      x_{k+1} = P_{S_m} ∘ … ∘ P_{S_1}(x_k + h f(x_k))                 (paper 000, eq. 4)
//   PNGS     the same sweep repeated until ‖P^itr(y) − y‖ ≤ abstol + reltol ‖y‖     (eq. 38)
//   PGS      every S_j linearised at y = x_k + h f(x_k), sweeps of projections onto the
//            half-spaces until (38)
//   Penalty  explicit Euler of x' = f(x) − γ Σ_j d_{S_j}(x) ∇d_{S_j}(x)
//
// Constraint evaluations are counted as the paper's work measure: one per set visited in a sweep
// (m per PBD step; m per PNGS sweep; m for the PGS linearisation plus m per PGS sweep; m per
// penalty step, whose Σ_j visits every set once).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "moreau/common/enum_names.h"
#include "moreau/common/field_list.h"
#include "moreau/common/steps.h"
#include "moreau/common/termination.h"
#include "moreau/pbd/constraints.h"
#include "moreau/pbd/drift.h"

namespace moreau::pbd {

enum class Method { kPBD, kPNGS, kPGS, kPenalty };
inline constexpr EnumNames<Method, 4> kMethodNames{{{Method::kPBD, "pbd"},
                                                    {Method::kPNGS, "pngs"},
                                                    {Method::kPGS, "pgs"},
                                                    {Method::kPenalty, "penalty"}}};

// "pbd", "pngs", "pgs", "penalty" — the names files and flags use.
std::string_view MethodName(Method method);
// Throws InputError for an unknown name.
Method ParseMethod(std::string_view name);

struct StepperOptions {
  Method method = Method::kPBD;
  // Time step h > 0.
  double h = 1e-3;
  // PNGS/PGS stopping criterion (38): stop once a sweep moves the iterate by at most
  // abstol + reltol · ‖y‖. Both ≥ 0 and not both 0.
  double abstol = 1e-12;
  double reltol = 1e-10;
  // Cap on sweeps per step for PNGS/PGS; a step that hits it is counted in capped_steps.
  int max_sweeps = 10000;
  // Penalty parameter γ > 0 of the penalty method.
  double penalty = 100.0;
  // Evaluate the constraint violation after every step (for max_violation); costs about one
  // sweep per step.
  bool monitor_violation = true;

  static const FieldList<StepperOptions>& Fields();  // key, range, help of every field
  // Throws InputError(key, reason).
  void Validate() const;
  // {"method", "h", "abstol", "reltol", "max_sweeps", "penalty", "monitor_violation"}
  nlohmann::json ToJson() const;
};

struct StepCounters {
  std::int64_t steps = 0;
  std::int64_t constraint_evaluations = 0;
  std::int64_t sweeps = 0;
  std::int64_t capped_steps = 0;  // PNGS/PGS steps that stopped at max_sweeps
};

struct SimulationSummary {
  Method method = Method::kPBD;
  double h = 0.0;
  double final_time = 0.0;
  StepCounters counters;
  double max_violation = 0.0;  // max over all steps of Constraints::MaxViolation
  double total_seconds = 0.0;  // the whole time loop
  Termination termination = Termination::kCompleted;  // kCompleted or kNonFinite
  std::string message;  // why it stopped early, with the step and time
  std::int64_t failed_step = -1;
  StepperOptions options;  // the settings used

  bool ok() const { return IsSuccess(termination); }
  std::string BriefReport() const;
  // SummaryJson + method, h, steps, final_time, constraint_evaluations, sweeps, capped_steps,
  // max_violation, failed_step (when it failed) and settings.
  nlohmann::json ToJson() const;
};

// One time stepper with its preallocated workspace. Holds references: the drift and the
// constraints must outlive it.
class TimeStepper {
 public:
  // Validates the options and the dimensions (throws InputError).
  TimeStepper(const Drift& drift, Constraints& constraints, const StepperOptions& options);

  // x ← Φ_h(x). A drift value that is not finite (NaN, ±∞) makes every entry of x NaN.
  void Step(VectorRef x);

  const StepCounters& counters() const { return counters_; }
  const StepperOptions& options() const { return options_; }

 private:
  bool Converged(const Vector& before, const Vector& after) const;

  const Drift& drift_;
  Constraints& constraints_;
  StepperOptions options_;
  StepCounters counters_;
  Vector f_;
  Vector previous_;
  LinearizedConstraints linearized_;
};

// Called with (k, t_k, x_k) for k = 0 (the initial state) … n; returns whether to go on.
using Observer = std::function<bool(std::int64_t, double, ConstVectorRef)>;

// Runs n = T/h steps from x0 (T/h must be a whole number to within 1e−9, else InputError).
// Stops early, with termination kNonFinite and the last finite state in *final_state, if the
// state stops being finite, or with kInterrupted when the observer returns false or a stop was
// requested (common/stop.h; the state is that of the last step taken). final_state may be null.
SimulationSummary Simulate(const Drift& drift, Constraints& constraints,
                           const StepperOptions& options, ConstVectorRef x0, double T,
                           const Observer& observer = {}, Vector* final_state = nullptr);

}  // namespace moreau::pbd
