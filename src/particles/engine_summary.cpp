// EngineOptions and EngineSummary: names, validation, JSON and the one-line report.
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "moreau/particles/engine.h"

namespace moreau::particles {

std::string_view SweepOrderName(SweepOrder order) { return EnumName(kSweepOrderNames, order); }

SweepOrder ParseSweepOrder(std::string_view name) {
  if (name == "colored") return SweepOrder::kColoured;
  return ParseEnumName(kSweepOrderNames, name, "sweep order");
}

const FieldList<EngineOptions>& EngineOptions::Fields() {
  using O = EngineOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Number("h", &O::h, Range::Positive(), "time", "time step h")
        .Integer("seed", &O::seed, Range::Any(), "", "noise key (Philox)")
        .Choice("order", &O::order, kSweepOrderNames, "sweep order")
        .Choice("search", &O::search, kNeighbourSearchNames,
                "neighbour search (brute_force: O(N²), for tests of the grid)")
        .Number("skin_factor", &O::skin_factor, Range::Positive(), "",
                "Verlet skin = skin_factor · max r")
        .Integer("threads", &O::threads, Range::NonNegative(), "",
                 "OpenMP threads (0: automatic); results do not depend on it")
        .Integer("block_cells", &O::block_cells, Range::NonNegative(), "cells",
                 "colouring block edge (0: automatic from the cell count)")
        .Integer("sweeps", &O::sweeps, Range::AtLeast(1), "", "PBD sweeps per step")
        .Flag("monitor_overlap", &O::monitor_overlap,
              "track the largest pair overlap after every step")
        .Flag("check_initial_state", &O::check_initial_state,
              "reject a start with overlaps beyond initial_tolerance")
        .Number("initial_tolerance", &O::initial_tolerance, Range::NonNegative(), "length",
                "overlap allowed in the start")
        .Integer("memory_limit", &O::memory_limit_bytes, Range::NonNegative(), "bytes",
                 "memory limit for the particle count (0: what is available)");
    return t;
  }();
  return list;
}

void EngineOptions::Validate() const { Fields().Validate(*this); }

nlohmann::json EngineOptions::ToJson() const { return Fields().ToJson(*this); }

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
