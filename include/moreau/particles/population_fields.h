// Agents coupled to diffusing fields (docs/fields.md "Agents and fields"): what each agent type
// does with each substrate of a fields::FieldSet that a Population carries.
//
// At every rule step (Δt = interval · h), before the user rule and the built-in rules, the
// population
//   1. clears the field's sources and deposits every agent's terms (FieldSet::Deposit, volume
//      V_i = π r_i² in 2D, 4/3 π r_i³ in 3D): secretion rate s toward the saturation c*, uptake
//      rate u, and an amount rate r (amount/time); s and r are multiplied by max(0, v_i) when
//      the type names a user variable v (`secretion_variable`: 0 switches it off);
//   2. steps the field `substeps` times by Δt / substeps (the field's time stays the engine's);
//   3. samples c and ∇c at every agent (FieldSet::Sample, the coupling's interpolation).
// The rules then read the samples:
//   proliferation  a type with `proliferation_above` c_p > 0 grows and divides (its own rules)
//                  only while c ≥ c_p;
//   necrosis       an agent with c < `necrosis_below` c_n (> 0) dies (a death), or becomes the
//                  type `necrotic_type` when one is named (it stays, with that type's rules);
//   chemotaxis     until the next rule step the agent drifts with
//                    v = χ ∇c / (1 + ‖∇c‖ / g)     (g = `gradient_saturation`; g = 0: χ ∇c),
//                  added to the motility (sampled again after the rule step's new roster, at the
//                  agents' new positions, so daughters sense where they are).
// Everything is summed in agent order and each grid line solved alone: the same bits for any
// thread count.
#pragma once

#include <string>
#include <vector>

#include "moreau/common/field_list.h"
#include "moreau/fields/field_set.h"

namespace moreau::particles {

struct PopulationRules;

// What agents of one type do with one substrate (scenario keys types.<type>.<substrate>.<key>).
struct SubstrateResponse {
  std::string type;                 // the agent type's name
  std::string substrate;            // the substrate's name
  double secretion_rate = 0.0;      // s ≥ 0 (1/time): toward the saturation c*
  double saturation = 0.0;          // c* ≥ 0 (amount/volume)
  double uptake_rate = 0.0;         // u ≥ 0 (1/time)
  double amount_rate = 0.0;         // r ≥ 0 (amount/time): a source carried by the agent
  std::string secretion_variable;   // "" or a user variable v: s and r times max(0, v_i)
  double chemotaxis = 0.0;          // χ (length²/(time · amount/volume)); < 0: away from c
  double gradient_saturation = 0.0;  // g ≥ 0 (amount/volume/length); 0: no saturation
  double proliferation_above = 0.0;  // c_p ≥ 0: grows and divides only while c ≥ c_p (0: always)
  double necrosis_below = 0.0;       // c_n ≥ 0: dies (or turns necrotic) when c < c_n (0: never)
  std::string necrotic_type;         // "" (dies) or the type a necrotic agent becomes

  // The fields above but type and substrate (they address the entry).
  static const FieldList<SubstrateResponse>& Fields();
};

struct FieldCouplingOptions {
  fields::Interpolation interpolation = fields::Interpolation::kVoxel;
  int substeps = 1;  // field steps per rule step, ≥ 1
  std::vector<SubstrateResponse> responses;  // at most one per (type, substrate)

  // interpolation, substeps.
  static const FieldList<FieldCouplingOptions>& Fields();
  // Throws InputError naming the key: "types.cell.oxygen.uptake_rate", "types.cell.sugar"
  // (unknown substrate), "types.cell.oxygen.necrotic_type" (unknown type), "…secretion_variable"
  // (unknown variable), an entry given twice.
  void Validate(const PopulationRules& rules, const fields::FieldSet& fields) const;
};

// The volume (the area in 2D) of an agent of radius r: π r² or 4/3 π r³.
double AgentVolume(int dimension, double radius);

// The saturating chemotactic velocity χ ∇c / (1 + ‖∇c‖ / g) of k components (g = 0: χ ∇c),
// added to `velocity`.
void AddChemotaxis(int dimension, double chi, double saturation, const double* gradient,
                   double* velocity);

}  // namespace moreau::particles
