// FieldSet: construction and checks, the arrays, totals and checkpoints.
#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <omp.h>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

void ValidateSubstrates(const std::vector<Substrate>& substrates) {
  if (substrates.empty()) throw InputError("substrates", "needs at least one substrate");
  std::set<std::string_view> names;
  for (const Substrate& s : substrates) {
    try {
      Substrate::Fields().Validate(s);
    } catch (const InputError& e) {
      throw e.Under(s.name.empty() ? "substrates" : "substrates." + s.name);
    }
    if (!names.insert(s.name).second) {
      throw InputError("substrates", fmt::format("the name '{}' is used twice", s.name));
    }
  }
}

}  // namespace

FieldSet::FieldSet(Grid grid, std::vector<Substrate> substrates, int threads)
    : grid_(std::move(grid)), substrates_(std::move(substrates)), threads_(threads) {
  try {
    grid_.Validate();
  } catch (const InputError& e) {
    throw e.Under("grid");
  }
  ValidateSubstrates(substrates_);
  if (threads_ < 0) throw InputError("threads", fmt::format("must be ≥ 0 (got {})", threads_));
  if (threads_ == 0) threads_ = std::max(1, omp_get_max_threads());
  threads_ = std::min(threads_, std::max(1, omp_get_num_procs()));  // more only wait
  const std::size_t count = substrates_.size();
  // Before any allocation: five arrays of doubles per voxel and substrate (the values and the
  // four source terms). The product in double: up to 10⁹ voxels per axis pass the grid's check.
  const std::array<int, 3> cells = grid_.cells();
  const double voxels = static_cast<double>(cells[0]) * cells[1] * cells[2];
  try {
    CheckMemory(fmt::format("{:.3g} voxels × {} substrates", voxels, count),
                5.0 * sizeof(double) * voxels * static_cast<double>(count));
  } catch (const InputError& e) {
    throw InputError("grid.spacing", e.what());
  }
  const auto n = static_cast<std::size_t>(grid_.voxel_count());
  values_.resize(count);
  for (std::size_t s = 0; s < count; ++s) values_[s].assign(n, substrates_[s].initial);
  for (auto* sources : {&secretion_, &secretion_target_, &uptake_, &source_}) {
    sources->assign(count, std::vector<double>(n, 0.0));
  }
  sources_written_.assign(count, 0);
}

int FieldSet::SubstrateIndex(std::string_view name) const {
  std::string known;
  for (std::size_t s = 0; s < substrates_.size(); ++s) {
    if (substrates_[s].name == name) return static_cast<int>(s);
    known += (known.empty() ? "" : ", ") + substrates_[s].name;
  }
  throw InputError(fmt::format("unknown substrate '{}' (substrates: {})", name, known));
}

std::span<double> FieldSet::secretion(int s) { return SourcesFor(secretion_, s); }
std::span<double> FieldSet::secretion_target(int s) { return SourcesFor(secretion_target_, s); }
std::span<double> FieldSet::uptake(int s) { return SourcesFor(uptake_, s); }
std::span<double> FieldSet::source(int s) { return SourcesFor(source_, s); }

std::span<double> FieldSet::SourcesFor(std::vector<std::vector<double>>& term, int s) {
  std::vector<double>& v = term.at(static_cast<std::size_t>(s));
  sources_written_[static_cast<std::size_t>(s)] = 1;
  return v;
}

void FieldSet::ClearSources() {
  for (auto* sources : {&secretion_, &secretion_target_, &uptake_, &source_}) {
    for (std::vector<double>& v : *sources) std::fill(v.begin(), v.end(), 0.0);
  }
}

double FieldSet::Total(int s) const {
  double sum = 0.0;
  for (double c : values_.at(static_cast<std::size_t>(s))) sum += c;
  return sum * grid_.voxel_volume();
}

void FieldSet::Restore(std::vector<std::vector<double>> values, double time, std::int64_t steps) {
  if (values.size() != values_.size()) {
    throw InputError("values", fmt::format("has {} substrates, the field set {}", values.size(),
                                           values_.size()));
  }
  for (std::size_t s = 0; s < values.size(); ++s) {
    if (values[s].size() != values_[s].size()) {
      throw InputError("values",
                       fmt::format("substrate '{}' has {} voxels, the grid {}", substrates_[s].name,
                                   values[s].size(), values_[s].size()));
    }
  }
  if (!std::isfinite(time)) throw InputError("time", "must be finite");
  if (steps < 0) throw InputError("steps", fmt::format("must be ≥ 0 (got {})", steps));
  values_ = std::move(values);
  time_ = time;
  steps_ = steps;
}

}  // namespace moreau::fields
