// The population's user code and user variables (population.h): the view over the population's
// storage, the user drift before every step, the user rule before the built-in rules, and the
// variables' inheritance at a division.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

std::size_t Population::VariableIndex(std::string_view name) const {
  std::string known;
  for (std::size_t v = 0; v < rules_.variables.size(); ++v) {
    if (rules_.variables[v].name == name) return v;
    known += (v > 0 ? ", " : "") + rules_.variables[v].name;
  }
  throw InputError(fmt::format("unknown variable '{}' (variables: {})", name,
                               known.empty() ? "none declared" : known));
}

PopulationView Population::View() {
  PopulationView view;
  view.dimension = geometry_.dimension;
  view.step = engine_.step();
  view.time = engine_.time();
  view.rule_dt = static_cast<double>(rules_.interval) * engine_.options().h;
  view.agents = agents_;
  for (std::vector<double>& values : variables_) view.variables.emplace_back(values);
  view.population = this;
  return view;
}

std::span<const double> Population::CurrentPositions() {
  if (agents_.empty()) return {};  // none left: the engine is stale
  if (!positions_current_) {
    view_positions_.resize(static_cast<std::size_t>(geometry_.dimension) * agents_.size());
    engine_.CopyPositions(view_positions_);
    positions_current_ = true;
  }
  return view_positions_;
}

// velocity = motility + the user's drift, for the next engine step. The drift writes into
// velocity_, zero on entry; the engine's one pass checks it, adds the motility, stores it in the
// engine's order and leaves velocity_ zero again (no second pass to clear it).
void Population::ApplyDrift() {
  const std::size_t size = static_cast<std::size_t>(geometry_.dimension) * agents_.size();
  if (!velocity_zero_ || velocity_.size() != size) velocity_.assign(size, 0.0);
  velocity_zero_ = false;  // until the engine has taken it
  const std::size_t n_before = agents_.size();
  drift_(View(), velocity_);
  if (agents_.size() != n_before) throw InputError("drift", "must not change the agents");
  const int bad = engine_.TakeActiveVelocities(velocity_, motility_);
  velocity_zero_ = true;
  if (bad < 0) return;
  const auto i = static_cast<std::size_t>(bad);
  throw NumericalError(
      fmt::format("step {}: the user drift gave agent {} (id {}) a non-finite velocity",
                  engine_.step(), i, agents_[i].id));
}

// The user rule's marks (N flags each), and a check of what it may change.
void Population::ApplyUserRule(std::vector<std::uint8_t>* divide, std::vector<std::uint8_t>* die) {
  divide->assign(agents_.size(), 0);
  die->assign(agents_.size(), 0);
  std::vector<std::int64_t> ids(agents_.size());
  for (std::size_t i = 0; i < agents_.size(); ++i) ids[i] = agents_[i].id;
  PopulationView view = View();
  rule_(view, *divide, *die);
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    const Agent& a = agents_[i];
    if (a.id != ids[i]) {
      throw InputError("rule",
                       fmt::format("changed the id of agent {} ({} → {})", i, ids[i], a.id));
    }
    if (!(a.radius > 0.0) || !std::isfinite(a.radius)) {
      throw InputError("rule", fmt::format("gave agent {} (id {}) the radius {} (must be > 0)", i,
                                           a.id, a.radius));
    }
    if (a.type < 0 || static_cast<std::size_t>(a.type) >= rules_.types.size()) {
      throw InputError("rule", fmt::format("gave agent {} (id {}) the type {} (must be in [0, {}))",
                                           i, a.id, a.type, rules_.types.size()));
    }
  }
}

// Agent `mother`'s variables appended to *next: once, or twice at a division (kCopy: the value
// for both; kSplit: half for each).
void Population::Inherit(std::size_t mother, bool divides,
                         std::vector<std::vector<double>>* next) const {
  for (std::size_t v = 0; v < variables_.size(); ++v) {
    const double value = variables_[v][mother];
    std::vector<double>& out = (*next)[v];
    if (!divides) {
      out.push_back(value);
    } else if (rules_.variables[v].inherit == Inheritance::kSplit) {
      out.insert(out.end(), {0.5 * value, 0.5 * value});
    } else {
      out.insert(out.end(), {value, value});
    }
  }
}

}  // namespace moreau::particles
