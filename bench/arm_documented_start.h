// The arm model's documented continuation start for the benchmarks (control_bench, ipopt_bench):
// read from examples/control/arm_2d.toml, so the benchmarks solve what the example documents.
#pragma once

#include <toml++/toml.h>

#include "moreau/control/continuation.h"

namespace moreau::bench {

// The documented start: [continuation] and [newton] of examples/control/arm_2d.toml, read from
// the file (a key the file leaves out keeps its default).
inline control::ContinuationOptions ArmDocumentedStart() {
  const toml::table file = toml::parse_file(MOREAU_SOURCE_DIR "/examples/control/arm_2d.toml");
  control::ContinuationOptions o;
  const toml::node_view c = file["continuation"];
  o.path_start = c["path_start"].value_or(o.path_start);
  o.path_increase = c["path_increase"].value_or(o.path_increase);
  o.stiffness_start = c["stiffness_start"].value_or(o.stiffness_start);
  o.stiffness_increase = c["stiffness_increase"].value_or(o.stiffness_increase);
  o.gamma_start = c["gamma_start"].value_or(o.gamma_start);
  o.gamma_decrease = c["gamma_decrease"].value_or(o.gamma_decrease);
  o.min_increase = c["min_increase"].value_or(o.min_increase);
  o.max_solves = c["max_solves"].value_or(o.max_solves);
  o.fixed_point.sweeps = file["fixed_point"]["sweeps"].value_or(o.fixed_point.sweeps);
  o.newton.residual_tolerance =
      file["newton"]["residual_tolerance"].value_or(o.newton.residual_tolerance);
  o.newton.max_iterations = file["newton"]["max_iterations"].value_or(o.newton.max_iterations);
  o.Validate();
  return o;
}

}  // namespace moreau::bench
