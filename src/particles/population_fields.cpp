// The agents' coupling to diffusing fields (population_fields.h): the field lists, the checks,
// and the population's part of a rule step: deposit, field steps, samples, and what the rules
// read from them (proliferation, necrosis, chemotaxis).
#include "moreau/particles/population_fields.h"

#include <cmath>
#include <numbers>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/particles/population.h"

namespace moreau::particles {

const FieldList<SubstrateResponse>& SubstrateResponse::Fields() {
  using R = SubstrateResponse;
  static const FieldList<R> list = [] {
    const Range rate = Range::NonNegative();
    FieldList<R> t;
    t.Number("secretion_rate", &R::secretion_rate, rate, "1/time", "s: secretion toward c*")
        .Number("saturation", &R::saturation, rate, "amount/volume", "c*: the secretion's target")
        .Number("uptake_rate", &R::uptake_rate, rate, "1/time", "u: uptake, −u c per volume")
        .Number("amount_rate", &R::amount_rate, rate, "amount/time", "r: a source per agent")
        .Text("secretion_variable", &R::secretion_variable,
              "a user variable v: secretion and amount rate times max(0, v) (\"\": constant)")
        .Number("chemotaxis", &R::chemotaxis, Range::Any(), "length²/(time·amount/volume)",
                "χ: drift χ ∇c / (1 + |∇c|/g) (< 0: away)")
        .Number("gradient_saturation", &R::gradient_saturation, rate, "amount/volume/length",
                "g: the chemotaxis saturates at |∇c| ≫ g (0: linear)")
        .Number("proliferation_above", &R::proliferation_above, rate, "amount/volume",
                "grows and divides only while c ≥ this (0: always)")
        .Number("necrosis_below", &R::necrosis_below, rate, "amount/volume",
                "dies (or turns necrotic_type) when c < this (0: never)")
        .Text("necrotic_type", &R::necrotic_type,
              "the type a necrotic agent becomes (\"\": it dies)");
    return t;
  }();
  return list;
}

const FieldList<FieldCouplingOptions>& FieldCouplingOptions::Fields() {
  using O = FieldCouplingOptions;
  static const FieldList<O> list = [] {
    FieldList<O> t;
    t.Choice("interpolation", &O::interpolation, fields::kInterpolationNames,
             "deposit and sample: the agent's voxel, or cloud-in-cell (linear)")
        .Integer("substeps", &O::substeps, Range::AtLeast(1), "", "field steps per rule step");
    return t;
  }();
  return list;
}

void FieldCouplingOptions::Validate(const PopulationRules& rules,
                                    const fields::FieldSet& fields) const {
  Fields().Validate(*this);
  std::set<std::pair<std::string, std::string>> seen;
  for (const SubstrateResponse& r : responses) {
    const std::string at = "types." + r.type;
    try {
      (void)rules.TypeIndex(r.type);
    } catch (const InputError& e) {
      throw InputError("types", e.what());
    }
    try {
      (void)fields.SubstrateIndex(r.substrate);
    } catch (const InputError& e) {
      throw InputError(at + "." + r.substrate, e.what());
    }
    const std::string key = at + "." + r.substrate;
    if (!seen.insert({r.type, r.substrate}).second) throw InputError(key, "given twice");
    try {
      SubstrateResponse::Fields().Validate(r);
    } catch (const InputError& e) {
      throw e.Under(key);
    }
    if (!r.necrotic_type.empty()) {
      try {
        (void)rules.TypeIndex(r.necrotic_type);
      } catch (const InputError& e) {
        throw InputError(key + ".necrotic_type", e.what());
      }
      if (r.necrotic_type == r.type) {
        throw InputError(key + ".necrotic_type", "must be another type than '" + r.type + "'");
      }
    }
    if (r.secretion_variable.empty()) continue;
    bool declared = false;
    for (const AgentVariable& v : rules.variables) declared = declared || v.name == r.secretion_variable;
    if (!declared) {
      throw InputError(key + ".secretion_variable",
                       fmt::format("unknown variable '{}'", r.secretion_variable));
    }
  }
}

double AgentVolume(int dimension, double radius) {
  return dimension == 3 ? 4.0 / 3.0 * std::numbers::pi * radius * radius * radius
                        : std::numbers::pi * radius * radius;
}

void AddChemotaxis(int dimension, double chi, double saturation, const double* gradient,
                   double* velocity) {
  double norm2 = 0.0;
  for (int a = 0; a < dimension; ++a) norm2 += gradient[a] * gradient[a];
  const double scale = saturation > 0.0 ? chi / (1.0 + std::sqrt(norm2) / saturation) : chi;
  for (int a = 0; a < dimension; ++a) velocity[a] += scale * gradient[a];
}

}  // namespace moreau::particles
