#include "moreau/pbd/study.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "moreau/common/error.h"
#include "moreau/common/stop.h"
#include "moreau/common/summary_json.h"

namespace moreau::pbd {

MethodSpec ParseMethodSpec(const std::string& text) {
  MethodSpec spec;
  spec.label = text;
  const std::size_t colon = text.find(':');
  spec.method = ParseMethod(text.substr(0, colon));
  if (colon != std::string::npos) {
    if (spec.method != Method::kPenalty) {
      throw InputError(fmt::format("method '{}': only penalty takes a parameter", text));
    }
    const std::string value = text.substr(colon + 1);
    char* end = nullptr;
    spec.penalty = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !(spec.penalty > 0.0) || !std::isfinite(spec.penalty)) {
      throw InputError(fmt::format("method '{}': the penalty γ must be a number > 0", text));
    }
  }
  return spec;
}

ParticleSystemModel::ParticleSystemModel(std::shared_ptr<const particles::ParticleModel> model,
                                         ParticleConstraintsOptions options)
    : model_(std::move(model)), options_(options) {
  if (!model_) throw InputError("model: a particle system model needs a particle model");
}

std::unique_ptr<Constraints> ParticleSystemModel::MakeWorkspace() const {
  return std::make_unique<ParticleConstraints>(model_, options_);
}

Vector SampledTrajectory::At(double t) const {
  MOREAU_ASSERT(!states_.empty() && dt_ > 0.0);
  const double s = t / dt_;
  const double last = static_cast<double>(states_.size() - 1);
  if (s < -1e-9 || s > last + 1e-9) {
    throw InputError(fmt::format("time {} is outside the reference [0, {}]", t, end_time()));
  }
  const double k = std::round(s);
  if (std::abs(s - k) <= 1e-9) return states_[static_cast<std::size_t>(k)];
  const auto k0 = static_cast<std::size_t>(std::floor(s));
  const double w = s - static_cast<double>(k0);
  return (1.0 - w) * states_[k0] + w * states_[k0 + 1];
}

SampledTrajectory ComputeReference(const StudyProblem& problem, const StepperOptions& options,
                                   double sample_dt) {
  const std::int64_t stride = StepCount(sample_dt, options.h);
  SampledTrajectory reference(sample_dt);
  auto constraints = problem.constraints->MakeWorkspace();
  const SimulationSummary summary =
      Simulate(*problem.drift, *constraints, options, problem.x0, problem.T,
               [&](std::int64_t k, double, ConstVectorRef x) {
                 if (k % stride == 0) reference.Append(x);
                 return true;
               });
  if (summary.termination == Termination::kInterrupted) {
    throw Interrupted("reference solution: " + summary.message);
  }
  if (!summary.ok()) throw NumericalError("reference solution: " + summary.message);
  return reference;
}

StudyRow RunStudyPoint(const StudyProblem& problem, const MethodSpec& spec, double h,
                       const StepperOptions& base) {
  StepperOptions options = base;
  options.method = spec.method;
  options.h = h;
  if (spec.penalty > 0.0) options.penalty = spec.penalty;
  auto constraints = problem.constraints->MakeWorkspace();
  double error = 0.0;
  const SimulationSummary summary =
      Simulate(*problem.drift, *constraints, options, problem.x0, problem.T,
               [&](std::int64_t, double t, ConstVectorRef x) {
                 error = std::max(error, (x - problem.solution(t)).norm());
                 return true;
               });
  StudyRow row;
  row.label = spec.label;
  row.method = spec.method;
  row.h = h;
  row.termination =
      summary.ok() && !std::isfinite(error) ? Termination::kNonFinite : summary.termination;
  row.error = row.ok() ? error : std::numeric_limits<double>::infinity();
  row.constraint_evaluations = summary.counters.constraint_evaluations;
  row.sweeps = summary.counters.sweeps;
  row.max_violation = summary.max_violation;
  row.total_seconds = summary.total_seconds;
  row.message = summary.ok() && !row.ok() ? "the error is not finite" : summary.message;
  return row;
}

std::vector<StudyRow> RunStudy(const StudyProblem& problem, const std::vector<MethodSpec>& methods,
                               const std::vector<double>& hs, const StepperOptions& base,
                               const std::function<void(int, int)>& progress) {
  std::vector<StudyRow> rows;
  const int total = static_cast<int>(methods.size() * hs.size());
  for (const MethodSpec& spec : methods) {
    for (double h : hs) {
      rows.push_back(RunStudyPoint(problem, spec, h, base));
      if (progress) progress(static_cast<int>(rows.size()), total);
    }
  }
  return rows;
}

nlohmann::json StudyRow::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, total_seconds);
  j["h"] = h;
  j["error"] = FiniteOrNull(error);
  j["constraint_evaluations"] = constraint_evaluations;
  j["sweeps"] = sweeps;
  j["max_violation"] = FiniteOrNull(max_violation);
  return j;
}

double ObservedOrder(const std::vector<double>& h, const std::vector<double>& error) {
  MOREAU_ASSERT(h.size() == error.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (!(error[i] > 0.0) || !std::isfinite(error[i]) || !(h[i] > 0.0)) continue;
    const double lx = std::log(h[i]);
    const double ly = std::log(error[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++n;
  }
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const double denom = n * sxx - sx * sx;
  if (!(std::abs(denom) > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return (n * sxy - sx * sy) / denom;
}

double ErrorAtBudget(const std::vector<StudyRow>& rows, const std::string& label, double budget) {
  std::vector<std::pair<double, double>> curve;  // (log evaluations, log error)
  for (const StudyRow& r : rows) {
    if (r.label != label || !r.ok() || !(r.error > 0.0)) continue;
    curve.emplace_back(std::log(static_cast<double>(r.constraint_evaluations)), std::log(r.error));
  }
  std::sort(curve.begin(), curve.end());
  const double lb = std::log(budget);
  for (std::size_t i = 0; i + 1 < curve.size(); ++i) {
    const auto [x0, y0] = curve[i];
    const auto [x1, y1] = curve[i + 1];
    if (lb >= x0 && lb <= x1) {
      if (x1 == x0) return std::exp(std::min(y0, y1));
      return std::exp(y0 + (y1 - y0) * (lb - x0) / (x1 - x0));
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace moreau::pbd
