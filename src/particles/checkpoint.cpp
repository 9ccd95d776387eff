#include "moreau/particles/checkpoint.h"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/hash.h"
#include "moreau/common/input_file.h"

namespace moreau::particles {

namespace {

constexpr char kMagic[8] = {'M', 'O', 'R', 'E', 'A', 'U', 'C', 'K'};
constexpr std::size_t kHeader = 24;  // magic, payload size, payload hash

// The counters of EngineStats by name (the timings included: they carry on).
template <typename F>
void ForEachStat(EngineStats& s, F&& f) {
  f("steps", s.steps);
  f("time", s.time);
  f("neighbour_list_builds", s.neighbour_list_builds);
  f("verlet_retries", s.verlet_retries);
  f("shortest_rebuild_interval", s.shortest_rebuild_interval);
  f("candidate_pairs", s.candidate_pairs);
  f("constraint_evaluations", s.constraint_evaluations);
  f("constraint_sets", s.constraint_sets);
  f("projections", s.projections);
  f("max_overlap", s.max_overlap);
  f("last_overlap", s.last_overlap);
  f("setup_seconds", s.setup_seconds);
  f("force_seconds", s.force_seconds);
  f("neighbour_seconds", s.neighbour_seconds);
  f("sweep_seconds", s.sweep_seconds);
  f("monitor_seconds", s.monitor_seconds);
  f("total_seconds", s.total_seconds);
}

template <typename T>
void Get(const nlohmann::json& j, const char* key, T* out) {
  const auto it = j.find(key);
  if (it == j.end()) throw InputError(fmt::format("checkpoint: {} is missing", key));
  try {
    it->get_to(*out);
  } catch (const nlohmann::json::exception&) {
    throw InputError(fmt::format("checkpoint: {} has the wrong type", key));
  }
}

void PutU64(std::string* s, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) s->push_back(static_cast<char>((v >> (8 * b)) & 0xffU));
}

std::uint64_t GetU64(const std::string& s, std::size_t at) {
  std::uint64_t v = 0;
  for (int b = 7; b >= 0; --b) {
    v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(b)]);
  }
  return v;
}

}  // namespace

nlohmann::json EngineState::ToJson() const {
  nlohmann::json j = {{"dimension", dimension},
                      {"count", count},
                      {"step", step},
                      {"slot_ids", slot_ids},
                      {"current", current},
                      {"reference", reference},
                      {"skin", skin},
                      {"drift_bound", drift_bound},
                      {"last_build_step", last_build_step},
                      {"shortest_rebuild_interval", shortest_rebuild_interval},
                      {"grid_lo", grid_lo},
                      {"grid_hi", grid_hi},
                      {"grid_reach", grid_reach}};
  EngineStats s = stats;
  nlohmann::json& js = j["stats"];
  ForEachStat(s, [&](const char* key, auto& v) { js[key] = v; });
  return j;
}

EngineState EngineState::FromJson(const nlohmann::json& j) {
  if (!j.is_object()) throw InputError("checkpoint: the engine state is not an object");
  EngineState s;
  Get(j, "dimension", &s.dimension);
  Get(j, "count", &s.count);
  Get(j, "step", &s.step);
  Get(j, "slot_ids", &s.slot_ids);
  Get(j, "current", &s.current);
  Get(j, "reference", &s.reference);
  Get(j, "skin", &s.skin);
  Get(j, "drift_bound", &s.drift_bound);
  Get(j, "last_build_step", &s.last_build_step);
  Get(j, "shortest_rebuild_interval", &s.shortest_rebuild_interval);
  std::array<double, 3> lo{}, hi{};
  Get(j, "grid_lo", &lo);
  Get(j, "grid_hi", &hi);
  std::copy(lo.begin(), lo.end(), s.grid_lo);
  std::copy(hi.begin(), hi.end(), s.grid_hi);
  Get(j, "grid_reach", &s.grid_reach);
  const auto it = j.find("stats");
  if (it == j.end() || !it->is_object()) throw InputError("checkpoint: stats is missing");
  ForEachStat(s.stats, [&](const char* key, auto& v) { Get(*it, key, &v); });
  return s;
}

namespace {

// Arrays of doubles as CBOR byte strings (the machine's little-endian doubles, every bit kept).
nlohmann::json BytesOf(const std::vector<std::vector<double>>& arrays) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::vector<double>& a : arrays) {
    std::vector<std::uint8_t> bytes(a.size() * sizeof(double));
    if (!a.empty()) std::memcpy(bytes.data(), a.data(), bytes.size());
    out.push_back(nlohmann::json::binary(std::move(bytes)));
  }
  return out;
}

void GetBytes(const nlohmann::json& j, const char* key, std::vector<std::vector<double>>* out) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_array()) {
    throw InputError(fmt::format("checkpoint: fields.{} is missing", key));
  }
  for (const nlohmann::json& item : *it) {
    if (!item.is_binary() || item.get_binary().size() % sizeof(double) != 0) {
      throw InputError(fmt::format("checkpoint: fields.{} is not an array of doubles", key));
    }
    const auto& bytes = item.get_binary();
    std::vector<double> a(bytes.size() / sizeof(double));
    if (!a.empty()) std::memcpy(a.data(), bytes.data(), bytes.size());
    out->push_back(std::move(a));
  }
}

nlohmann::json FieldsJson(const PopulationState& s) {
  return {{"values", BytesOf(s.field_values)},
          {"samples", BytesOf(s.field_samples)},
          {"gradients", BytesOf(s.field_gradients)},
          {"time", s.field_time},
          {"steps", s.field_steps}};
}

void FieldsFromJson(const nlohmann::json& j, PopulationState* s) {
  GetBytes(j, "values", &s->field_values);
  GetBytes(j, "samples", &s->field_samples);
  GetBytes(j, "gradients", &s->field_gradients);
  Get(j, "time", &s->field_time);
  Get(j, "steps", &s->field_steps);
}

}  // namespace

nlohmann::json PopulationState::ToJson() const {
  nlohmann::json a = nlohmann::json::object();
  for (const Agent& x : agents) {
    a["id"].push_back(x.id);
    a["type"].push_back(x.type);
    a["generation"].push_back(x.generation);
    a["divisions"].push_back(x.divisions);
    a["radius"].push_back(x.radius);
    a["age"].push_back(x.age);
    for (const double p : x.polarity) a["polarity"].push_back(p);
    a["mother"].push_back(x.mother);
  }
  const PopulationSummary& c = counters;
  nlohmann::json j = {{"agents", a},
          {"variables", variables},
          {"last_positions", last_positions},
          {"last_deaths", last_deaths},
          {"last_removals", last_removals},
          {"overlap_before", overlap_before},
          {"stopped", stopped},
          {"counters",
           {{"termination", ToString(c.termination)},
            {"message", c.message},
            {"rule_steps", c.rule_steps},
            {"births", c.births},
            {"deaths", c.deaths},
            {"removals", c.removals},
            {"relax_sweeps", c.relax_sweeps},
            {"final_count", c.final_count},
            {"max_overlap_before", c.max_overlap_before},
            {"rules_seconds", c.rules_seconds},
            {"total_seconds", c.total_seconds}}}};
  if (!field_values.empty()) j["fields"] = FieldsJson(*this);
  return j;
}

namespace {

// The agents from their columns (PopulationState::ToJson).
std::vector<Agent> AgentsFromJson(const nlohmann::json& a) {
  if (!a.is_object()) throw InputError("checkpoint: agents is not an object");
  std::vector<std::int64_t> id, mother;
  std::vector<int> type, generation, divisions;
  std::vector<double> radius, age, polarity;
  if (!a.empty()) {
    Get(a, "id", &id);
    Get(a, "type", &type);
    Get(a, "generation", &generation);
    Get(a, "divisions", &divisions);
    Get(a, "radius", &radius);
    Get(a, "age", &age);
    Get(a, "polarity", &polarity);
    Get(a, "mother", &mother);
  }
  const std::size_t n = id.size();
  if (type.size() != n || generation.size() != n || divisions.size() != n || radius.size() != n ||
      age.size() != n || polarity.size() != 3 * n || mother.size() != n) {
    throw InputError("checkpoint: the agents' columns differ in length");
  }
  std::vector<Agent> agents(n);
  for (std::size_t i = 0; i < n; ++i) {
    agents[i] = {id[i],
                 type[i],
                 generation[i],
                 divisions[i],
                 radius[i],
                 age[i],
                 {polarity[3 * i], polarity[3 * i + 1], polarity[3 * i + 2]},
                 mother[i]};
  }
  return agents;
}

}  // namespace

PopulationState PopulationState::FromJson(const nlohmann::json& j, EngineState engine) {
  if (!j.is_object()) throw InputError("checkpoint: the population state is not an object");
  PopulationState s;
  s.engine = std::move(engine);
  const auto agents = j.find("agents");
  if (agents == j.end()) throw InputError("checkpoint: agents is missing");
  s.agents = AgentsFromJson(*agents);
  Get(j, "variables", &s.variables);
  Get(j, "last_positions", &s.last_positions);
  Get(j, "last_deaths", &s.last_deaths);
  Get(j, "last_removals", &s.last_removals);
  Get(j, "overlap_before", &s.overlap_before);
  Get(j, "stopped", &s.stopped);
  const auto it = j.find("counters");
  if (it == j.end() || !it->is_object()) throw InputError("checkpoint: counters is missing");
  PopulationSummary& c = s.counters;
  std::string termination;
  Get(*it, "termination", &termination);
  c.termination = ParseTermination(termination);
  Get(*it, "message", &c.message);
  Get(*it, "rule_steps", &c.rule_steps);
  Get(*it, "births", &c.births);
  Get(*it, "deaths", &c.deaths);
  Get(*it, "removals", &c.removals);
  Get(*it, "relax_sweeps", &c.relax_sweeps);
  Get(*it, "final_count", &c.final_count);
  Get(*it, "max_overlap_before", &c.max_overlap_before);
  Get(*it, "rules_seconds", &c.rules_seconds);
  Get(*it, "total_seconds", &c.total_seconds);
  if (const auto f = j.find("fields"); f != j.end()) FieldsFromJson(*f, &s);
  return s;
}

void WriteCheckpoint(const std::filesystem::path& path, const EngineState& state,
                     const nlohmann::json& run) {
  const std::vector<std::uint8_t> payload =
      nlohmann::json::to_cbor(nlohmann::json{{"engine", state.ToJson()}, {"run", run}});
  const std::string_view bytes(reinterpret_cast<const char*>(payload.data()), payload.size());
  std::string header(kMagic, sizeof kMagic);
  PutU64(&header, payload.size());
  PutU64(&header, HashBytes(bytes));
  const std::filesystem::path tmp = path.string() + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) {
    throw InputError(fmt::format("{}: cannot create the checkpoint", tmp.string()));
  }
  const bool written = std::fwrite(header.data(), 1, header.size(), f) == header.size() &&
                       std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() &&
                       std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  if (std::fclose(f) != 0 || !written) {
    std::filesystem::remove(tmp);
    throw InputError(fmt::format("{}: writing the checkpoint failed", tmp.string()));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw InputError(fmt::format("{}: cannot replace the checkpoint", path.string()));
}

EngineState ReadCheckpoint(const std::filesystem::path& path, nlohmann::json* run) {
  const std::string where = path.string() + ": checkpoint: ";
  if (const std::string why = NotAnInputFile(path.string()); !why.empty()) {
    throw InputError(where + "cannot be opened: the path " + why);  // a folder, FIFO, device
  }
  const std::string data = ReadInputFile(path.string());
  if (data.size() < kHeader || std::memcmp(data.data(), kMagic, sizeof kMagic) != 0) {
    throw InputError(where + "not a moreau checkpoint");
  }
  const std::uint64_t size = GetU64(data, 8);
  const std::string_view payload = std::string_view(data).substr(kHeader);
  if (size != payload.size() || GetU64(data, 16) != HashBytes(payload)) {
    throw InputError(where + "truncated or corrupt (size or hash mismatch)");
  }
  try {
    const nlohmann::json j = nlohmann::json::from_cbor(payload);
    if (!j.is_object() || !j.contains("engine") || !j.contains("run")) {
      throw InputError("checkpoint: engine or run is missing");
    }
    *run = j.at("run");
    return EngineState::FromJson(j.at("engine"));
  } catch (const nlohmann::json::exception&) {
    throw InputError(where + "malformed payload");
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

}  // namespace moreau::particles
