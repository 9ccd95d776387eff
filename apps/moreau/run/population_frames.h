// What a population run records as it goes (docs/abm.md, "What a run writes"): the lineage of
// every agent that lived (lineage.csv) and the trajectory frames with the agents' arrays
// (trajectory.h5 + .xdmf, vtu/frame.pvd).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/io/grid_writer.h"
#include "moreau/io/trajectory.h"
#include "moreau/particles/population.h"
#include "output.h"
#include "run/particles_scenario.h"

namespace moreau::cli {

// Every agent that lived: its display id (a dense index in the order of first appearance: the
// initial agents 0 … N0 − 1 in index order, then each rule step's daughters in index order), its
// mother, its birth and its end. Observe the population at step 0 and after every rule step
// (the run's observer), and once more at the end.
class Lineage {
 public:
  void Observe(const particles::Population& population);
  // The display id of agent `id` (seen by Observe).
  std::int64_t DisplayId(std::int64_t id) const { return rows_[row_.at(id)].display_id; }
  // "id,display_id,mother,mother_display_id,type,type_name,generation,birth_time,end_time,fate",
  // one row per agent in display-id order; mother −1 for the initial agents, end_time empty
  // and fate "alive" for those alive at the end, fate "died" or "removed" otherwise.
  std::string Csv(const particles::PopulationRules& rules) const;
  // Checkpoints: every row and when the departures were last taken; Resume takes them back
  // (InputError "checkpoint: …" for a malformed state).
  nlohmann::json State() const;
  void Resume(const nlohmann::json& state);

 private:
  struct Row {
    std::int64_t id, display_id, mother;
    int type, generation;
    double birth;
    std::optional<double> end;
    const char* fate = "alive";
  };
  void End(const std::vector<std::int64_t>& ids, double t, const char* fate);
  std::vector<Row> rows_;
  std::unordered_map<std::int64_t, std::size_t> row_;  // id → its row
  std::int64_t rule_steps_ = -1;                       // when the departures were last taken
};

// The trajectory frames (HDF5 + XDMF and/or VTU; the count changes per frame): positions, ids and
// radii, and per agent the arrays type, generation, divisions, mother, display_id, age, polarity
// (3 components), contacts (the engine's ContactCounts with the rules' contact_factor) and each
// user variable by its name ("variable_NAME" when the name is taken or has a '/'), with the
// types' names as the string list "type_names"; written at the rule steps that cross a multiple
// of the stride. With diffusing fields the same frames of every substrate (by its name) go to
// fields.h5 + fields.xdmf (with the trajectory's HDF5) and vti/fields.pvd (with its VTU).
class PopulationFrames {
 public:
  PopulationFrames(OutputDir& out, const ParticleScenario& scenario, std::int64_t stride);
  // Writes a frame when the step is in a new stride slot (or `force`).
  void Write(const particles::Population& p, const Lineage& lineage, bool force);
  void Close();
  // Checkpoints: frames are kept from now on; State() holds them and the last stride slot;
  // Resume writes a state's frames and takes its slot (a resumed run).
  void KeepFrames() { keep_frames_ = true; }
  nlohmann::json State() const;
  void Resume(const nlohmann::json& state);

 private:
  // Writes the frame held in the member arrays (and keeps it when asked).
  void Emit(std::int64_t step, double t, int k, const std::vector<double>& x,
            const std::vector<std::vector<double>>& variables);
  // Writes one frame of the fields (per substrate its values) and keeps it when asked.
  void EmitFields(std::int64_t step, double t, const std::vector<std::vector<double>>& values);
  void ResumeFields(const nlohmann::json& frames);
  std::int64_t stride_;
  std::int64_t last_slot_ = -1;
  std::vector<std::unique_ptr<io::TrajectoryWriter>> writers_;
  std::vector<std::unique_ptr<io::GridWriter>> grid_writers_;  // fields.h5, vti/fields.pvd
  std::vector<std::string> substrate_names_;
  std::vector<std::string> variable_names_;  // the array name of each user variable
  std::vector<std::int64_t> ids_, type_, generation_, divisions_, mother_, display_, contacts_;
  std::vector<double> radii_, age_, polarity_;
  bool keep_frames_ = false;
  nlohmann::json kept_ = nlohmann::json::array();  // the frames written so far
  nlohmann::json kept_fields_ = nlohmann::json::array();  // the fields' frames written so far
};

}  // namespace moreau::cli
