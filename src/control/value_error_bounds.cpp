#include "moreau/control/value_error_bounds.h"

#include <fmt/format.h>

#include <cmath>

#include "moreau/common/error.h"

namespace moreau::control {

void ValueErrorConstants::Validate() const {
  auto check = [](const char* field, double value) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw InputError(
          fmt::format("study.theorem.{}: must be a finite number ≥ 0 (got {})", field, value));
    }
  };
  check("c1", c1);
  check("c2", c2);
  check("c3", c3);
  check("delta", delta);
}

nlohmann::json ValueErrorConstants::ToJson() const {
  return {{"c1", c1}, {"c2", c2}, {"c3", c3}, {"delta", delta}};
}

ValueErrorBounds Theorem51Bounds(const ValueErrorConstants& c, double horizon, double dt) {
  c.Validate();
  const double e = std::exp(c.c2 * horizon);
  ValueErrorBounds b;
  b.lower = -0.5 * c.c1 * c.c2 * horizon * ((e - 1.0) * dt + dt * dt) -
            0.5 * c.c1 * c.c3 * (e - 1.0) * dt - horizon * c.delta;
  b.upper = 0.5 * c.c1 * c.c2 * (c.c3 + 1.0) * e * horizon * dt + horizon * c.delta;
  return b;
}

}  // namespace moreau::control
