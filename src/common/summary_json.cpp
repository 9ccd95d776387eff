#include "moreau/common/summary_json.h"

#include <string>

namespace moreau {

nlohmann::json SummaryJson(Termination termination, std::string_view message,
                           double total_seconds) {
  return {{"termination", std::string(ToString(termination))},
          {"ok", IsSuccess(termination)},
          {"message", std::string(message)},
          {"total_seconds", total_seconds}};
}

}  // namespace moreau
