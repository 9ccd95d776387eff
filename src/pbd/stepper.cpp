#include "moreau/pbd/stepper.h"

#include <fmt/format.h>
#include <cmath>
#include <limits>

#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "moreau/common/stopwatch.h"
#include "moreau/common/summary_json.h"

namespace moreau::pbd {

std::string_view MethodName(Method method) { return EnumName(kMethodNames, method); }

Method ParseMethod(std::string_view name) { return ParseEnumName(kMethodNames, name, "method"); }

const FieldList<StepperOptions>& StepperOptions::Fields() {
  using O = StepperOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Choice("method", &O::method, kMethodNames, "time stepping method")
        .Number("h", &O::h, Range::Positive(), "time", "time step h")
        .Number("abstol", &O::abstol, Range::NonNegative(), "",
                "PNGS/PGS: absolute sweep tolerance")
        .Number("reltol", &O::reltol, Range::NonNegative(), "",
                "PNGS/PGS: relative sweep tolerance")
        .Integer("max_sweeps", &O::max_sweeps, Range::Closed(1, 1e9), "",
                 "PNGS/PGS: sweeps per step at most")
        .Number("penalty", &O::penalty, Range::Positive(), "", "penalty parameter γ")
        .Flag("monitor_violation", &O::monitor_violation,
              "evaluate the constraint violation after every step (about one sweep)")
        .Rule("reltol", [](const O& o) {
          return o.abstol == 0.0 && o.reltol == 0.0 ? "abstol and reltol are both 0" : "";
        });
    return t;
  }();
  return list;
}

void StepperOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json StepperOptions::ToJson() const { return Fields().ToJson(*this); }

nlohmann::json SimulationSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["method"] = std::string(MethodName(method));
  j["h"] = h;
  j["steps"] = counters.steps;
  j["final_time"] = final_time;
  j["constraint_evaluations"] = counters.constraint_evaluations;
  j["sweeps"] = counters.sweeps;
  j["capped_steps"] = counters.capped_steps;
  j["max_violation"] = FiniteOrNull(max_violation);
  if (!ok()) j["failed_step"] = failed_step;
  j["settings"] = options.ToJson();
  return j;
}

std::string SimulationSummary::BriefReport() const {
  std::string s = fmt::format(
      "{}: h = {:g}, {} steps, {} constraint evaluations, {} sweeps, max violation {:.3e}, {:.3f} "
      "s",
      MethodName(method), h, counters.steps, counters.constraint_evaluations, counters.sweeps,
      max_violation, total_seconds);
  if (counters.capped_steps > 0)
    s += fmt::format(", {} steps hit max_sweeps", counters.capped_steps);
  if (!ok()) s += ": " + message;
  return s;
}

namespace {

// x.allFinite() in one vectorised pass without early exit (Simulate checks every step):
// v − v is +0 for every finite v and NaN for ±∞ and NaN, and a sum of zeros is 0.
bool AllFinite(const Vector& x) { return (x.array() - x.array()).sum() == 0.0; }

}  // namespace

TimeStepper::TimeStepper(const Drift& drift, Constraints& constraints,
                         const StepperOptions& options)
    : drift_(drift),
      constraints_(constraints),
      options_(options),
      f_(constraints.state_size()),
      previous_(constraints.state_size()) {
  options_.Validate();
}

bool TimeStepper::Converged(const Vector& before, const Vector& after) const {
  return (after - before).norm() <= options_.abstol + options_.reltol * before.norm();
}

void TimeStepper::Step(VectorRef x) {
  MOREAU_ASSERT(x.size() == constraints_.state_size());
  const std::int64_t m = constraints_.num_sets();
  const double h = options_.h;
  drift_.Evaluate(x, f_);
  ++counters_.steps;
  if (!AllFinite(f_)) {
    // A projection may map NaN back to a finite point (max and min drop it), so a non-finite
    // drift makes the whole state NaN: Simulate then stops with kNonFinite.
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  switch (options_.method) {
    case Method::kPBD:
      x += h * f_;
      constraints_.Sweep(x);
      counters_.constraint_evaluations += m;
      ++counters_.sweeps;
      break;
    case Method::kPNGS:
    case Method::kPGS: {
      x += h * f_;
      const bool linear = options_.method == Method::kPGS;
      if (linear) {
        constraints_.Linearize(x, &linearized_);
        counters_.constraint_evaluations += m;
      }
      int sweep = 0;
      bool converged = false;
      while (sweep < options_.max_sweeps && !converged) {
        previous_ = x;
        if (linear) {
          linearized_.Sweep(x);
        } else {
          constraints_.Sweep(x);
        }
        ++sweep;
        counters_.constraint_evaluations += m;
        converged = Converged(previous_, x);
      }
      counters_.sweeps += sweep;
      if (!converged) ++counters_.capped_steps;
      break;
    }
    case Method::kPenalty:
      previous_.setZero();
      constraints_.AddPenaltyDirection(x, previous_);
      x += h * (f_ - options_.penalty * previous_);
      counters_.constraint_evaluations += m;
      ++counters_.sweeps;
      break;
  }
}

SimulationSummary Simulate(const Drift& drift, Constraints& constraints,
                           const StepperOptions& options, ConstVectorRef x0, double T,
                           const Observer& observer, Vector* final_state) {
  if (x0.size() != constraints.state_size()) {
    throw InputError(fmt::format("initial state has size {}, the problem has dimension {}",
                                 x0.size(), constraints.state_size()));
  }
  const std::int64_t n = StepCount(T, options.h);
  TimeStepper stepper(drift, constraints, options);
  SimulationSummary summary;
  summary.method = options.method;
  summary.h = options.h;
  summary.options = options;

  const Stopwatch stopwatch;
  Vector x = x0;
  Vector last_good = x0;
  bool go_on = (!observer || observer(0, 0.0, x)) && !StopRequested();
  std::int64_t done = 0;  // steps taken
  for (std::int64_t k = 1; k <= n && go_on; ++k) {
    stepper.Step(x);
    if (!AllFinite(x)) {
      summary.termination = Termination::kNonFinite;
      summary.failed_step = k;
      summary.message = fmt::format("state became non-finite at step {} (t = {:g}); kept step {}",
                                    k, static_cast<double>(k) * options.h, k - 1);
      x = last_good;
      break;
    }
    if (options.monitor_violation) {
      summary.max_violation = std::max(summary.max_violation, constraints.MaxViolation(x));
    }
    summary.final_time = static_cast<double>(k) * options.h;
    done = k;
    go_on = (!observer || observer(k, summary.final_time, x)) && !StopRequested();
    last_good = x;
  }
  if (!go_on && done < n) {
    summary.termination = Termination::kInterrupted;
    summary.message = fmt::format("stopped {} after step {}",
                                  StopRequested() ? "on request" : "by the observer", done);
  }
  summary.counters = stepper.counters();
  summary.total_seconds = stopwatch.Seconds();
  if (final_state != nullptr) *final_state = x;
  return summary;
}

}  // namespace moreau::pbd
