#include "moreau/common/summary_json.h"

#include <cmath>
#include <string>

namespace moreau {

nlohmann::json SummaryJson(Termination termination, std::string_view message,
                           double total_seconds) {
  return {{"termination", std::string(ToString(termination))},
          {"ok", IsSuccess(termination)},
          {"message", std::string(message)},
          {"total_seconds", total_seconds}};
}

nlohmann::json FiniteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string JsonText(const nlohmann::json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace moreau
