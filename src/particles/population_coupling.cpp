// The population's side of the coupling to diffusing fields (population_fields.h): the deposit
// of the agents' terms, the field steps and the samples at a rule step, and the rules that read
// the samples (necrosis, proliferation, chemotaxis).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

void Population::CoupleFields(fields::FieldSet fields, FieldCouplingOptions options) {
  if (fields.grid().dimension != geometry_.dimension) {
    throw InputError("fields.dimension",
                     fmt::format("must be the agents' dimension {} (got {})", geometry_.dimension,
                                 fields.grid().dimension));
  }
  if (engine_.step() != 0) throw InputError("fields", "must be coupled before the first step");
  options.Validate(rules_, fields);
  const auto substrates = static_cast<std::size_t>(fields.substrate_count());
  response_index_.assign(rules_.types.size() * substrates, -1);
  for (std::size_t r = 0; r < options.responses.size(); ++r) {
    const SubstrateResponse& response = options.responses[r];
    const auto t = static_cast<std::size_t>(rules_.TypeIndex(response.type));
    const auto s = static_cast<std::size_t>(fields.SubstrateIndex(response.substrate));
    response_index_[t * substrates + s] = static_cast<int>(r);
  }
  fields_.emplace(std::move(fields));
  coupling_ = std::move(options);
  SampleFields();
  motility_ = ActiveVelocities();
  engine_.SetActiveVelocities(motility_);
}

std::span<const double> Population::FieldSamples(int s) const {
  if (!fields_) return {};
  return field_samples_.at(static_cast<std::size_t>(s));
}

std::span<const double> Population::FieldGradients(int s) const {
  if (!fields_) return {};
  return field_gradients_.at(static_cast<std::size_t>(s));
}

namespace {

// The response of type t to substrate s, or nullptr.
const SubstrateResponse* ResponseOf(const std::vector<int>& index,
                                    const FieldCouplingOptions& coupling, int substrates, int t,
                                    int s) {
  const int r = index[static_cast<std::size_t>(t * substrates + s)];
  return r < 0 ? nullptr : &coupling.responses[static_cast<std::size_t>(r)];
}

}  // namespace

// Clears the sources, deposits every agent's terms, steps the fields over dt and samples them.
void Population::StepFields(std::span<const double> x, double dt) {
  fields::FieldSet& f = *fields_;
  f.ClearSources();
  const int k = geometry_.dimension;
  const std::size_t n = agents_.size();
  std::vector<double> volume(n), secretion(n), saturation(n), uptake(n), amount(n);
  for (std::size_t i = 0; i < n; ++i) volume[i] = AgentVolume(k, agents_[i].radius);
  std::vector<const double*> switch_of(coupling_.responses.size(), nullptr);  // its variable
  for (std::size_t r = 0; r < switch_of.size(); ++r) {
    const std::string& name = coupling_.responses[r].secretion_variable;
    if (!name.empty()) switch_of[r] = variables_[VariableIndex(name)].data();
  }
  for (int s = 0; s < f.substrate_count(); ++s) {
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
      const SubstrateResponse* r =
          ResponseOf(response_index_, coupling_, f.substrate_count(), agents_[i].type, s);
      const double* on_of =
          r != nullptr ? switch_of[static_cast<std::size_t>(r - coupling_.responses.data())]
                       : nullptr;
      const double on = on_of != nullptr ? std::max(0.0, on_of[i]) : 1.0;
      secretion[i] = r != nullptr ? on * r->secretion_rate : 0.0;
      saturation[i] = r != nullptr ? r->saturation : 0.0;
      uptake[i] = r != nullptr ? r->uptake_rate : 0.0;
      amount[i] = r != nullptr ? on * r->amount_rate : 0.0;
      any = any || r != nullptr;
    }
    if (any) {
      f.Deposit(s, x, volume, secretion, saturation, uptake, amount, coupling_.interpolation);
    }
  }
  const double h = dt / coupling_.substeps;
  for (int step = 0; step < coupling_.substeps; ++step) f.Step(h);
  SampleFields();
}

void Population::SampleFields() {
  const fields::FieldSet& f = *fields_;
  const std::span<const double> x = CurrentPositions();
  const std::size_t n = agents_.size();
  const auto k = static_cast<std::size_t>(geometry_.dimension);
  field_samples_.resize(static_cast<std::size_t>(f.substrate_count()));
  field_gradients_.resize(field_samples_.size());
  for (int s = 0; s < f.substrate_count(); ++s) {
    std::vector<double>& value = field_samples_[static_cast<std::size_t>(s)];
    std::vector<double>& gradient = field_gradients_[static_cast<std::size_t>(s)];
    value.assign(n, 0.0);
    gradient.assign(k * n, 0.0);
    if (n > 0) f.Sample(s, x, coupling_.interpolation, value, gradient);
  }
  samples_current_ = true;
}

// Necrosis and proliferation of agent i (state a, its type possibly changed here): true when it
// dies; *starved when it may neither grow nor divide.
bool Population::FieldFate(std::size_t i, Agent* a, bool* starved) const {
  const int substrates = fields_->substrate_count();
  for (int s = 0; s < substrates; ++s) {
    const SubstrateResponse* r = ResponseOf(response_index_, coupling_, substrates, a->type, s);
    if (r == nullptr) continue;
    const double c = field_samples_[static_cast<std::size_t>(s)][i];
    if (r->necrosis_below > 0.0 && c < r->necrosis_below) {
      if (r->necrotic_type.empty()) return true;
      a->type = rules_.TypeIndex(r->necrotic_type);  // its thresholds act from the next rule step
      *starved = true;
      return false;
    }
    if (r->proliferation_above > 0.0 && c < r->proliferation_above) *starved = true;
  }
  return false;
}

bool Population::HasChemotaxis() const {
  if (!fields_ || !samples_current_) return false;
  return std::any_of(coupling_.responses.begin(), coupling_.responses.end(),
                     [](const SubstrateResponse& r) { return r.chemotaxis != 0.0; });
}

// Adds every agent's chemotactic velocity (k·N) by the current samples.
void Population::AddFieldDrift(std::vector<double>* velocity) const {
  const int k = geometry_.dimension;
  const auto uk = static_cast<std::size_t>(k);
  const int substrates = fields_->substrate_count();
  velocity->resize(uk * agents_.size(), 0.0);
  for (std::size_t i = 0; i < agents_.size(); ++i) {
    for (int s = 0; s < substrates; ++s) {
      const SubstrateResponse* r =
          ResponseOf(response_index_, coupling_, substrates, agents_[i].type, s);
      if (r == nullptr || r->chemotaxis == 0.0) continue;
      AddChemotaxis(k, r->chemotaxis, r->gradient_saturation,
                    field_gradients_[static_cast<std::size_t>(s)].data() + uk * i,
                    velocity->data() + uk * i);
    }
  }
}

}  // namespace moreau::particles
