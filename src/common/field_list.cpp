#include "moreau/common/field_list.h"

#include <cmath>

namespace moreau {

Range Range::Because(std::string reason) const {
  Range r = *this;
  r.why = std::move(reason);
  return r;
}

bool Range::Contains(double v) const {
  if (std::isnan(v)) return false;
  const bool above = min_open ? v > min : v >= min;
  const bool below = max_open ? v < max : v <= max;
  return above && below;
}

std::string Range::Describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return fmt::format("in {}{}, {}{}", min_open ? "(" : "[", min, max, max_open ? ")" : "]");
  }
  if (has_min) return fmt::format("{} {}", min_open ? ">" : "≥", min);
  if (has_max) return fmt::format("{} {}", max_open ? "<" : "≤", max);
  return "";
}

std::string Range::Violation(double v, std::string_view got) const {
  if (Contains(v)) return "";
  return fmt::format("must be {} (got {}){}{}", Describe(), got, why.empty() ? "" : " ", why);
}

std::string NumberViolation(const Range& range, double v) {
  if (!std::isfinite(v)) return "must be a finite number";
  return range.Violation(v, fmt::format("{}", v));
}

void SetDotted(nlohmann::json& j, std::string_view key, nlohmann::json value) {
  nlohmann::json* node = &j;
  std::size_t start = 0;
  for (std::size_t dot = key.find('.'); dot != std::string_view::npos;
       start = dot + 1, dot = key.find('.', start)) {
    node = &(*node)[std::string(key.substr(start, dot - start))];
  }
  (*node)[std::string(key.substr(start))] = std::move(value);
}

std::string ExpectedType(std::string_view what, const nlohmann::json& got) {
  const char* type = got.is_string()           ? "a string"
                     : got.is_number_integer() ? "an integer"
                     : got.is_number()         ? "a number"
                     : got.is_boolean()        ? "a boolean"
                     : got.is_array()          ? "an array"
                     : got.is_null()           ? "nothing"
                                               : "a table";
  return fmt::format("expected {}, got {}", what, type);
}

}  // namespace moreau
