// The scenario of `moreau control`: model = "oscillator", "arm" (the thesis examples) or
// "network" (a spring network and sampled references from the file), the discretisation, the
// continuation and Newton options and the study options, read through one field table per model.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "field_table.h"
#include "moreau/control/continuation.h"
#include "moreau/control/examples.h"
#include "moreau/control/spring_network.h"
#include "moreau/control/tracking_problem.h"
#include "moreau/control/value_error_bounds.h"
#include "scenario.h"

namespace moreau::cli {

// model = "network": the network, the horizon, the cost and the sampled reference.
struct NetworkSettings {
  int dimension = 2;
  std::vector<control::NetworkNode> nodes;
  std::vector<control::NetworkSpring> springs;
  double horizon = 0.0;  // T (required)
  double gamma = 1e-4;   // γ
  control::CostWeights cost;
  Eigen::MatrixXd positions;   // frames × (d · free nodes)
  Eigen::MatrixXd velocities;  // optional, same shape
  Eigen::MatrixXd weights;     // optional, frames × free nodes
};

struct ControlScenario {
  std::string model;  // "oscillator", "arm" or "network"
  control::OscillatorExample oscillator;
  control::ArmExample arm;
  std::optional<double> arm_bounds_time;  // default T/2
  NetworkSettings network;
  int steps = 512;  // N
  control::ContinuationOptions continuation;
  bool warm_start = false;  // study: Newton from the interpolated coarser solution first
  int compare_samples = 0;  // study: instants for diff_finest (0: the coarsest grid's nodes)
  std::optional<control::ValueErrorConstants> theorem;  // study: Theorem 5.1 bounds
};

// Reads and validates every key, builds the target problem once so that every model error
// surfaces before any output; throws InputError "FILE: KEY: REASON".
// Every key of a control scenario of `model` (oscillator, arm, network).
const FieldTable<ControlScenario>& ControlFields(const std::string& model);

ControlScenario ReadControlScenario(Scenario& scenario);

// The settings used, keyed as in the scenario file.
nlohmann::json EchoControlScenario(const ControlScenario& scenario);

// The problem family of the model (path fraction p ∈ (0, 1]; p = 1 is the target). Throws
// InputError "KEY: REASON" for an invalid network or reference.
control::ProblemFamily MakeProblemFamily(const ControlScenario& scenario);

// Structured network fields (control/network_fields.cpp).
void ReadNetworkNodes(Scenario& s, ControlScenario& c, const std::string& key);
void ReadNetworkSprings(Scenario& s, ControlScenario& c, const std::string& key);
// A frames × values matrix (array of arrays of numbers), or nothing when absent.
void ReadReferenceMatrix(Scenario& s, const std::string& key, Eigen::MatrixXd* out);

}  // namespace moreau::cli
