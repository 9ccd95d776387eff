#include "run/population_frames.h"

#include <filesystem>
#include <string_view>

#include <fmt/format.h>

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
    arrays.push_back(PointArray::Float64(variable_names_[v], p.variable(v).data()));
  }
  const io::ParticleFrame frame{p.engine().step(),
                                p.engine().time(),
                                p.engine().dimension(),
                                x.data(),
                                ids_.data(),
                                radii_.data(),
                                p.count(),
                                arrays};
  for (auto& writer : writers_) writer->Write(frame);
}

void PopulationFrames::Close() {
  for (auto& writer : writers_) writer->Close();
}

}  // namespace moreau::cli
