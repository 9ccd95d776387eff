#include "field_table.h"

#include <algorithm>
#include <cmath>
#include <new>

namespace moreau::cli {

void CheckRange(const Scenario& scenario, std::string_view key, const Range& range, double v,
                std::string_view got) {
  const std::string why = range.Violation(v, got);
  if (!why.empty()) scenario.Fail(key, why);
}

nlohmann::json NodeToJson(const toml::node& node) {
  if (const auto v = node.value_exact<std::int64_t>()) return *v;
  if (const auto v = node.value_exact<double>()) return *v;
  if (const auto v = node.value_exact<bool>()) return *v;
  if (const auto v = node.value_exact<std::string>()) return *v;
  if (const toml::array* arr = node.as_array()) {
    nlohmann::json j = nlohmann::json::array();
    for (const toml::node& item : *arr) j.push_back(NodeToJson(item));
    return j;
  }
  return nlohmann::json::object();
}

std::int64_t CheckFrameCount(std::int64_t steps, std::int64_t stride) {
  const std::int64_t frames = steps / std::max<std::int64_t>(1, stride) + 1;
  if (frames > kMaxFrames) {
    throw InputError(fmt::format("{} frames ({} steps, one every {}) is more than the {} allowed",
                                 frames, steps, stride, kMaxFrames));
  }
  return frames;
}

void NamingAllocations(const Scenario& scenario, std::string_view key,
                       const std::function<void()>& work) {
  try {
    work();
  } catch (const std::bad_alloc&) {
    throw OutOfMemoryError(
        key.empty() ? fmt::format("{}: out of memory while checking the scenario", scenario.path())
                    : fmt::format("{}: {}: out of memory while reading this key", scenario.path(),
                                  key));
  }
}

void WithKey(const Scenario& scenario, std::string_view key, const std::function<void()>& check) {
  try {
    check();
  } catch (const ScenarioError&) {
    throw;  // names its file and key already
  } catch (const InputError& e) {
    if (e.key().empty()) scenario.Fail(key, e.reason());
    scenario.Fail(key.empty() ? e.key() : std::string(key) + "." + e.key(), e.reason());
  }
}

}  // namespace moreau::cli
