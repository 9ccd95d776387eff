#include "moreau/common/stop.h"

#include <atomic>

namespace moreau {
namespace {

std::atomic<int> g_stop_reason{0};
static_assert(std::atomic<int>::is_always_lock_free);

}  // namespace

bool RequestStop(int reason) noexcept {
  int none = 0;
  return g_stop_reason.compare_exchange_strong(none, reason);
}

int StopReason() noexcept { return g_stop_reason.load(std::memory_order_relaxed); }

void ClearStopRequest() noexcept { g_stop_reason.store(0); }

}  // namespace moreau
