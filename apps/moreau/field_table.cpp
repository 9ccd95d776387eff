#include "field_table.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace moreau::cli {

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

void Range::Check(const Scenario& scenario, std::string_view key, double v,
                  std::string_view got) const {
  if (Contains(v)) return;
  scenario.Fail(
      key, fmt::format("must be {} (got {}){}{}", Describe(), got, why.empty() ? "" : " ", why));
}

std::int64_t CheckFrameCount(std::int64_t steps, std::int64_t stride) {
  const std::int64_t frames = steps / std::max<std::int64_t>(1, stride) + 1;
  if (frames > kMaxFrames) {
    throw InputError(fmt::format("{} frames ({} steps, one every {}) is more than the {} allowed",
                                 frames, steps, stride, kMaxFrames));
  }
  return frames;
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

void NamingAllocations(const Scenario& scenario, std::string_view key,
                       const std::function<void()>& work) {
  try {
    work();
  } catch (const std::bad_alloc&) {
    throw OutOfMemoryError(
        fmt::format("{}: {}: out of memory while reading this key", scenario.path(), key));
  }
}

void WithKey(const Scenario& scenario, std::string_view key, const std::function<void()>& check) {
  try {
    check();
  } catch (const InputError& e) {
    // A message that already names the file (a nested table's Read) names its key too.
    const std::string_view reason = e.what();
    if (reason.starts_with(scenario.path() + ": ")) throw;
    // "KEY: reason" from a library Validate() that names the same key: keep the key once;
    // "KEY.SUB must …" names a key below KEY: name that one.
    const std::string own = std::string(key) + ": ";
    if (reason.starts_with(own)) scenario.Fail(key, reason.substr(own.size()));
    const std::size_t space = reason.find(' ');
    if (reason.starts_with(std::string(key) + ".") && space != std::string_view::npos) {
      scenario.Fail(reason.substr(0, space), reason.substr(space + 1));
    }
    scenario.Fail(key, reason);
  }
}

}  // namespace moreau::cli
