#include "run/fields_scenario.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {
namespace {

using PS = ParticleScenario;
using fields::Substrate;
using particles::FieldCouplingOptions;
using particles::SubstrateResponse;

// The keys of [fields] that are not substrates.
constexpr std::string_view kScalarKeys[] = {"spacing", "interpolation", "substeps"};

bool IsScalarKey(std::string_view key) {
  return std::find(std::begin(kScalarKeys), std::end(kScalarKeys), key) != std::end(kScalarKeys);
}

// One [fields.<name>] table: the keys of Substrate::Fields(); errors name fields.<name>.<key>.
Substrate ReadSubstrate(const Scenario& sc, const std::string& name, const toml::table& t) {
  Substrate sub;
  sub.name = name;
  for (const auto& [key, node] : t) {
    const std::string at = "fields." + name + "." + std::string(key.str());
    const auto* f = Substrate::Fields().Find(key.str());
    if (f == nullptr || key.str() == "name") sc.Fail(at, "unknown key");
    const std::string why = f->set(sub, NodeToJson(node));
    if (!why.empty()) sc.Fail(at, why);
  }
  return sub;
}

// [fields]: the scalar keys (read by their own fields) and a table per substrate.
void ReadSubstrates(Scenario& sc, PS& s, const std::string& key) {
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return;
  const toml::table* table = node->as_table();
  if (table == nullptr) sc.Fail(key, "expected a table ([fields])");
  for (const auto& [name, value] : *table) {
    const std::string at = key + "." + std::string(name.str());
    if (IsScalarKey(name.str())) continue;
    const toml::table* sub = value.as_table();
    if (sub == nullptr) {
      sc.Fail(at, "unknown key (a substrate is a table [fields.<name>]; keys: spacing, "
                  "interpolation, substeps)");
    }
    s.fields.substrates.push_back(ReadSubstrate(sc, std::string(name.str()), *sub));
  }
}

nlohmann::json EchoSubstrates(const PS& s) {
  if (!s.fields.enabled()) return nullptr;
  nlohmann::json j = nlohmann::json::object();
  for (const Substrate& sub : s.fields.substrates) {
    nlohmann::json one = Substrate::Fields().ToJson(sub);
    one.erase("name");
    j[sub.name] = std::move(one);
  }
  return j;
}

// Rows of `moreau keys` for keys read by a table's reader (not echoed: the reader echoes them).
template <class T>
void DocumentRows(FieldTable<PS>& t, const std::string& prefix, const FieldList<T>& list,
                  const T& defaults, std::initializer_list<std::string_view> skip) {
  for (const auto& f : list.fields()) {
    if (std::find(skip.begin(), skip.end(), f.key) != skip.end()) continue;
    const nlohmann::json value = f.get(defaults);
    const std::string help =
        f.help + (value.is_null() || value == "" ? "" : " (default " + value.dump() + ")");
    t.Custom(prefix + f.key, f.type, [](Scenario&, PS&, const std::string&) {}, nullptr, help);
  }
}

void CheckFields(const PS& s) {
  const FieldSettings& f = s.fields;
  if (!f.enabled()) {
    if (f.spacing) throw InputError("fields.spacing", "needs a substrate ([fields.<name>])");
    if (!f.coupling.responses.empty()) {
      const SubstrateResponse& r = f.coupling.responses.front();
      throw InputError(fmt::format("types.{}.{}", r.type, r.substrate),
                       "unknown substrate (no [fields.<name>] is given)");
    }
    return;
  }
  if (!s.is_population()) throw InputError("fields", "needs [[types]] (agents to couple)");
  if (!f.spacing) throw InputError("fields.spacing", "required key is missing");
  // The field set checks its memory before it allocates (fields.spacing).
  const fields::FieldSet set = s.MakeFields(1);
  try {
    f.coupling.Validate(s.MakeRules(), set);
  } catch (const InputError& e) {
    if (e.key().starts_with("interpolation") || e.key().starts_with("substeps")) {
      throw e.Under("fields");
    }
    throw;
  }
}

}  // namespace

void AddFieldCouplingFields(FieldTable<PS>& t) {
  t.Custom("fields", "[fields.<substrate>] tables", ReadSubstrates, EchoSubstrates,
           "diffusing substrates over the domain box, one table each (docs/fields.md)");
  DocumentRows(t, "fields.<substrate>.", Substrate::Fields(), Substrate{}, {"name"});
  t.OptionalNumber(
       "fields.spacing", [](auto& s) -> auto& { return s.fields.spacing; }, Range::Positive(),
       "h: the voxels' edge; the domain box must hold a whole number of voxels per axis")
      .Mount("fields", [](auto& s) -> auto& { return s.fields.coupling; },
             FieldCouplingOptions::Fields());
  DocumentRows(t, "types.<name>.<substrate>.", SubstrateResponse::Fields(), SubstrateResponse{},
               {});
  t.Check("", CheckFields);
}

// A table of a [[types]] entry that names a substrate: its response (types.<type>.<substrate>).
void ReadSubstrateResponse(const Scenario& sc, const std::string& type, const std::string& name,
                           const toml::table& table, FieldSettings* out) {
  SubstrateResponse r;
  r.type = type;
  r.substrate = name;
  for (const auto& [key, node] : table) {
    const std::string at = "types." + type + "." + name + "." + std::string(key.str());
    const auto* f = SubstrateResponse::Fields().Find(key.str());
    if (f == nullptr) sc.Fail(at, "unknown key");
    const std::string why = f->set(r, NodeToJson(node));
    if (!why.empty()) sc.Fail(at, why);
  }
  out->coupling.responses.push_back(std::move(r));
}

fields::Grid ParticleScenario::FieldGrid() const {
  fields::Grid grid;
  grid.dimension = dimension;
  grid.spacing = fields.spacing.value_or(1.0);
  for (std::size_t a = 0; a < 3; ++a) {
    grid.lower[a] = domain_lo[a];
    grid.upper[a] = domain_hi[a];
  }
  return grid;
}

fields::FieldSet ParticleScenario::MakeFields(int threads) const {
  const fields::Grid grid = FieldGrid();
  std::vector<Substrate> substrates = fields.substrates;
  for (Substrate& sub : substrates) {
    for (int face = 0; face < 2 * dimension; ++face) {
      fields::FaceBoundary& b = sub.boundary[static_cast<std::size_t>(face)];
      const bool wraps = periodic[static_cast<std::size_t>(face / 2)];
      if (wraps && b.kind == fields::BoundaryKind::kZeroFlux) b.kind = fields::BoundaryKind::kPeriodic;
      if (wraps != (b.kind == fields::BoundaryKind::kPeriodic)) {
        constexpr const char* kFace[] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
        throw InputError(fmt::format("fields.{}.{}", sub.name, kFace[face]),
                         wraps ? "must be periodic (the domain is periodic along this axis)"
                                  : "cannot be periodic (the domain is not periodic along this axis)");
      }
    }
  }
  try {
    return fields::FieldSet(grid, std::move(substrates), threads);
  } catch (const InputError& e) {
    const std::string& key = e.key();
    if (key.starts_with("grid.")) throw InputError("fields.spacing", e.reason());
    if (key.starts_with("substrates.")) throw InputError("fields." + key.substr(11), e.reason());
    throw InputError("fields", e.what());
  }
}

}  // namespace moreau::cli
