// EngineOptions and EngineSummary: names, validation, JSON and the one-line report.
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "moreau/particles/engine.h"

namespace moreau::particles {

std::string_view SweepOrderName(SweepOrder order) {
  return order == SweepOrder::kColoured ? "coloured" : "lexicographic";
}

SweepOrder ParseSweepOrder(std::string_view name) {
  if (name == "coloured" || name == "colored") return SweepOrder::kColoured;
  if (name == "lexicographic") return SweepOrder::kLexicographic;
  throw InputError(
      fmt::format("unknown sweep order '{}' (expected coloured or lexicographic)", name));
}

void EngineOptions::Validate() const {
  if (!(h > 0.0) || !std::isfinite(h)) throw InputError(fmt::format("h must be > 0 (got {})", h));
  if (!(skin_factor > 0.0) || !std::isfinite(skin_factor)) {
    throw InputError(fmt::format("skin_factor must be > 0 (got {})", skin_factor));
  }
  if (threads < 0) throw InputError(fmt::format("threads must be ≥ 0 (got {})", threads));
  if (sweeps < 1) throw InputError(fmt::format("sweeps must be ≥ 1 (got {})", sweeps));
  if (block_cells < 0) {
    throw InputError(fmt::format("block_cells must be ≥ 0 (got {})", block_cells));
  }
  if (!(initial_tolerance >= 0.0)) {
    throw InputError(fmt::format("initial_tolerance must be ≥ 0 (got {})", initial_tolerance));
  }
  if (memory_limit_bytes < 0) {
    throw InputError(fmt::format("memory_limit_bytes must be ≥ 0 (got {})", memory_limit_bytes));
  }
}

nlohmann::json EngineOptions::ToJson() const {
  return {{"h", h},
          {"seed", seed},
          {"order", SweepOrderName(order)},
          {"search", search == NeighbourSearch::kCellGrid ? "cell_grid" : "brute_force"},
          {"skin_factor", skin_factor},
          {"threads", threads},
          {"block_cells", block_cells},
          {"sweeps", sweeps},
          {"monitor_overlap", monitor_overlap},
          {"check_initial_state", check_initial_state},
          {"initial_tolerance", initial_tolerance},
          {"memory_limit_bytes", memory_limit_bytes}};
}

nlohmann::json EngineSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, stats.total_seconds);
  j["steps"] = stats.steps;
  j["final_time"] = stats.time;
  j["neighbour_list_builds"] = stats.neighbour_list_builds;
  j["verlet_retries"] = stats.verlet_retries;
  j["shortest_rebuild_interval"] = stats.shortest_rebuild_interval;
  j["candidate_pairs"] = stats.candidate_pairs;
  j["constraint_evaluations"] = stats.constraint_evaluations;
  j["constraint_sets_paper_count"] = stats.constraint_sets;
  j["projections"] = stats.projections;
  j["max_overlap"] = stats.max_overlap;
  j["last_overlap"] = stats.last_overlap;
  j["setup_seconds"] = stats.setup_seconds;
  j["force_seconds"] = stats.force_seconds;
  j["neighbour_seconds"] = stats.neighbour_seconds;
  j["sweep_seconds"] = stats.sweep_seconds;
  j["monitor_seconds"] = stats.monitor_seconds;
  if (failed_step >= 0) {
    j["failed_step"] = failed_step;
    if (failed_particle >= 0) j["failed_particle"] = failed_particle;
  }
  j["settings"] = settings.ToJson();
  return j;
}

std::string EngineSummary::BriefReport() const {
  std::string s = fmt::format(
      "steps {} t {:.6g} builds {} retries {} pairs {} max overlap {:.3g} wall {:.3f} s",
      stats.steps, stats.time, stats.neighbour_list_builds, stats.verlet_retries,
      stats.candidate_pairs, stats.max_overlap, stats.total_seconds);
  if (!ok()) s += " — " + message;
  return s;
}

}  // namespace moreau::particles
