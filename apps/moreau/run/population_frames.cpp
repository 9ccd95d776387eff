#include "run/population_frames.h"

#include <cstring>

#include <filesystem>
#include <string_view>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {

void Lineage::Observe(const particles::Population& population) {
  const double t = population.engine().time();
  for (const particles::Agent& a : population.agents()) {
    // Only an agent of age 0 can be new: an initial agent at the start, or a daughter (and her
    // mother) right after the rule step of the division; the others were seen a rule step ago.
    if (a.age > 0.0 || row_.contains(a.id)) continue;
    row_.emplace(a.id, rows_.size());
    rows_.push_back({a.id, static_cast<std::int64_t>(rows_.size()), a.mother, a.type, a.generation,
                     t, std::nullopt});
  }
  const std::int64_t rule_steps = population.summary().rule_steps;
  if (rule_steps == rule_steps_) return;  // these departures are in already
  rule_steps_ = rule_steps;
  End(population.last_deaths(), t, "died");
  End(population.last_removals(), t, "removed");
}

void Lineage::End(const std::vector<std::int64_t>& ids, double t, const char* fate) {
  for (const std::int64_t id : ids) {
    const auto it = row_.find(id);
    if (it == row_.end())
      continue;  // never observed (cannot happen with an observer per rule step)
    rows_[it->second].end = t;
    rows_[it->second].fate = fate;
  }
}

std::string Lineage::Csv(const particles::PopulationRules& rules) const {
  std::string csv =
      "id,display_id,mother,mother_display_id,type,type_name,generation,birth_time,end_time,fate\n";
  for (const Row& r : rows_) {
    const std::int64_t mother_display = r.mother < 0 ? -1 : DisplayId(r.mother);
    csv += fmt::format("{},{},{},{},{},{},{},{:.9g},{},{}\n", r.id, r.display_id, r.mother,
                       mother_display, r.type, rules.types[static_cast<std::size_t>(r.type)].name,
                       r.generation, r.birth, r.end ? fmt::format("{:.9g}", *r.end) : "", r.fate);
  }
  return csv;
}

nlohmann::json Lineage::State() const {
  nlohmann::json rows = nlohmann::json::array();
  for (const Row& r : rows_) {
    rows.push_back({r.id, r.display_id, r.mother, r.type, r.generation, r.birth,
                    r.end ? nlohmann::json(*r.end) : nlohmann::json(), r.fate});
  }
  return {{"rows", rows}, {"rule_steps", rule_steps_}};
}

void Lineage::Resume(const nlohmann::json& state) {
  try {
    rows_.clear();
    row_.clear();
    for (const nlohmann::json& r : state.at("rows")) {
      Row row{r.at(0).get<std::int64_t>(),
              r.at(1).get<std::int64_t>(),
              r.at(2).get<std::int64_t>(),
              r.at(3).get<int>(),
              r.at(4).get<int>(),
              r.at(5).get<double>(),
              std::nullopt,
              "alive"};
      if (!r.at(6).is_null()) row.end = r.at(6).get<double>();
      const std::string fate = r.at(7).get<std::string>();
      for (const char* f : {"alive", "died", "removed"}) row.fate = fate == f ? f : row.fate;
      if (row.fate != fate || row.display_id != static_cast<std::int64_t>(rows_.size()) ||
          !row_.emplace(row.id, rows_.size()).second) {
        throw InputError("checkpoint: the lineage is malformed");
      }
      rows_.push_back(row);
    }
    state.at("rule_steps").get_to(rule_steps_);
  } catch (const nlohmann::json::exception&) {
    throw InputError("checkpoint: the lineage is malformed");
  }
}

namespace {

// The array name of user variable `name`: the name, or "variable_NAME" ('/' as '_') when it is
// one a frame uses already or has a '/'.
std::string VariableArrayName(std::string name) {
  constexpr std::string_view kTaken[] = {"radius", "id",         "type", "generation", "divisions",
                                         "mother", "display_id", "age",  "polarity",   "contacts"};
  bool taken = name.find('/') != std::string::npos;
  for (const std::string_view t : kTaken) taken = taken || name == t;
  if (!taken && name.rfind("variable_", 0) != 0) return name;
  for (char& c : name) c = c == '/' ? '_' : c;
  return "variable_" + name;
}

}  // namespace

PopulationFrames::PopulationFrames(OutputDir& out, const ParticleScenario& scenario,
                                   std::int64_t stride)
    : stride_(stride) {
  const particles::PopulationRules rules = scenario.MakeRules();
  std::vector<io::StringList> lists(1, {"type_names", {}});
  for (const particles::AgentType& t : rules.types) lists[0].values.push_back(t.name);
  for (const particles::AgentVariable& v : rules.variables) {
    variable_names_.push_back(VariableArrayName(v.name));
  }
  if (scenario.output.hdf5) {
    out.Stage("trajectory.xdmf");  // the sidecar the HDF5 writer completes at Close()
    writers_.push_back(
        io::MakeHdf5Writer(out.Stage("trajectory.h5"), scenario.output.trajectory, lists));
  }
  if (scenario.output.vtu) {
    const std::filesystem::path dir = out.Stage("vtu");
    std::filesystem::create_directories(dir);
    writers_.push_back(io::MakeVtuSeriesWriter(dir, "frame", lists));
  }
  if (!scenario.fields.enabled()) return;
  const fields::Grid g = scenario.FieldGrid();
  io::GridSpec spec;
  spec.dimension = g.dimension;
  spec.origin = g.lower;
  spec.spacing = g.spacing;
  spec.cells = g.cells();
  for (const fields::Substrate& sub : scenario.fields.substrates) substrate_names_.push_back(sub.name);
  if (scenario.output.hdf5) {
    out.Stage("fields.xdmf");
    grid_writers_.push_back(io::MakeHdf5GridWriter(out.Stage("fields.h5"), spec));
  }
  if (scenario.output.vtu) {
    const std::filesystem::path dir = out.Stage("vti");
    std::filesystem::create_directories(dir);
    grid_writers_.push_back(io::MakeVtiSeriesWriter(dir, "fields", spec));
  }
}

void PopulationFrames::EmitFields(std::int64_t step, double t,
                                  const std::vector<std::vector<double>>& values) {
  if (keep_frames_) {
    nlohmann::json bytes = nlohmann::json::array();
    for (const std::vector<double>& v : values) {
      std::vector<std::uint8_t> b(v.size() * sizeof(double));
      if (!v.empty()) std::memcpy(b.data(), v.data(), b.size());
      bytes.push_back(nlohmann::json::binary(std::move(b)));
    }
    kept_fields_.push_back({{"step", step}, {"t", t}, {"values", std::move(bytes)}});
  }
  std::vector<io::GridArray> arrays;
  for (std::size_t s = 0; s < values.size(); ++s) arrays.push_back({substrate_names_[s], values[s]});
  for (auto& writer : grid_writers_) writer->Write({step, t, arrays});
}

void PopulationFrames::Write(const particles::Population& p, const Lineage& lineage, bool force) {
  const std::int64_t slot = p.engine().step() / stride_;
  if (writers_.empty() || (!force && slot == last_slot_)) return;
  last_slot_ = slot;
  const std::vector<double> x = p.count() > 0 ? p.Positions() : std::vector<double>{};
  for (auto* v : {&ids_, &type_, &generation_, &divisions_, &mother_, &display_}) v->clear();
  for (auto* v : {&radii_, &age_, &polarity_}) v->clear();
  for (const particles::Agent& a : p.agents()) {
    ids_.push_back(a.id);
    type_.push_back(a.type);
    generation_.push_back(a.generation);
    divisions_.push_back(a.divisions);
    mother_.push_back(a.mother);
    display_.push_back(lineage.DisplayId(a.id));
    radii_.push_back(a.radius);
    age_.push_back(a.age);
    polarity_.insert(polarity_.end(), a.polarity.begin(), a.polarity.end());
  }
  contacts_.clear();
  if (p.count() > 0) {
    for (const int c : p.engine().ContactCounts(p.rules().contact_factor)) contacts_.push_back(c);
  }
  std::vector<std::vector<double>> variables;
  for (std::size_t v = 0; v < variable_names_.size(); ++v) {
    variables.emplace_back(p.variable(v).begin(), p.variable(v).end());
  }
  Emit(p.engine().step(), p.engine().time(), p.engine().dimension(), x, variables);
  if (grid_writers_.empty() || p.fields() == nullptr) return;
  std::vector<std::vector<double>> values;
  for (int s = 0; s < p.fields()->substrate_count(); ++s) {
    values.emplace_back(p.fields()->values(s).begin(), p.fields()->values(s).end());
  }
  EmitFields(p.engine().step(), p.engine().time(), values);
}

void PopulationFrames::Emit(std::int64_t step, double t, int k, const std::vector<double>& x,
                            const std::vector<std::vector<double>>& variables) {
  if (keep_frames_) {
    kept_.push_back({{"step", step},
                     {"t", t},
                     {"k", k},
                     {"x", x},
                     {"id", ids_},
                     {"type", type_},
                     {"generation", generation_},
                     {"divisions", divisions_},
                     {"mother", mother_},
                     {"display", display_},
                     {"radius", radii_},
                     {"age", age_},
                     {"polarity", polarity_},
                     {"contacts", contacts_},
                     {"variables", variables}});
  }
  using io::PointArray;
  std::vector<PointArray> arrays{PointArray::Int64("type", type_.data()),
                                 PointArray::Int64("generation", generation_.data()),
                                 PointArray::Int64("divisions", divisions_.data()),
                                 PointArray::Int64("mother", mother_.data()),
                                 PointArray::Int64("display_id", display_.data()),
                                 PointArray::Float64("age", age_.data()),
                                 PointArray::Float64("polarity", polarity_.data(), 3),
                                 PointArray::Int64("contacts", contacts_.data())};
  for (std::size_t v = 0; v < variable_names_.size(); ++v) {
    arrays.push_back(PointArray::Float64(variable_names_[v], variables[v].data()));
  }
  const io::ParticleFrame frame{
      step,  t, k, x.data(), ids_.data(), radii_.data(), static_cast<std::int64_t>(ids_.size()),
      arrays};
  for (auto& writer : writers_) writer->Write(frame);
}

nlohmann::json PopulationFrames::State() const {
  nlohmann::json j = {{"frames", kept_}, {"last_slot", last_slot_}};
  if (!grid_writers_.empty()) j["field_frames"] = kept_fields_;
  return j;
}

void PopulationFrames::Resume(const nlohmann::json& state) {
  try {
    for (const nlohmann::json& f : state.at("frames")) {
      f.at("id").get_to(ids_);
      f.at("type").get_to(type_);
      f.at("generation").get_to(generation_);
      f.at("divisions").get_to(divisions_);
      f.at("mother").get_to(mother_);
      f.at("display").get_to(display_);
      f.at("radius").get_to(radii_);
      f.at("age").get_to(age_);
      f.at("polarity").get_to(polarity_);
      f.at("contacts").get_to(contacts_);
      const auto x = f.at("x").get<std::vector<double>>();
      const auto variables = f.at("variables").get<std::vector<std::vector<double>>>();
      const int k = f.at("k").get<int>();
      const std::size_t n = ids_.size();
      bool fits = variables.size() == variable_names_.size() &&
                  x.size() == n * static_cast<std::size_t>(k) && polarity_.size() == 3 * n;
      for (const std::vector<std::int64_t>* v :
           {&type_, &generation_, &divisions_, &mother_, &display_, &contacts_}) {
        fits = fits && v->size() == n;
      }
      for (const std::vector<double>& v : variables) fits = fits && v.size() == n;
      if (!fits || radii_.size() != n || age_.size() != n) {
        throw InputError("checkpoint: a frame does not fit the run");
      }
      Emit(f.at("step").get<std::int64_t>(), f.at("t").get<double>(), k, x, variables);
    }
    state.at("last_slot").get_to(last_slot_);
    if (!grid_writers_.empty()) ResumeFields(state.at("field_frames"));
  } catch (const nlohmann::json::exception&) {
    throw InputError("checkpoint: the run's frames are malformed");
  }
}

// The kept frames of the fields (State): written again, bit for bit.
void PopulationFrames::ResumeFields(const nlohmann::json& frames) {
  for (const nlohmann::json& f : frames) {
    std::vector<std::vector<double>> values;
    for (const nlohmann::json& item : f.at("values")) {
      const auto& bytes = item.get_binary();
      std::vector<double> v(bytes.size() / sizeof(double));
      if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(double));
      values.push_back(std::move(v));
    }
    if (values.size() != substrate_names_.size()) {
      throw InputError("checkpoint: a frame of the fields does not fit the run");
    }
    EmitFields(f.at("step").get<std::int64_t>(), f.at("t").get<double>(), values);
  }
}

void PopulationFrames::Close() {
  for (auto& writer : writers_) writer->Close();
  for (auto& writer : grid_writers_) writer->Close();
}

}  // namespace moreau::cli
