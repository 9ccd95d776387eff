#include "signals.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace moreau::cli {
namespace {

std::atomic<int> g_signal{0};       // the first SIGINT/SIGTERM received, or 0
std::atomic<int> g_scope_depth{0};  // live StopScopes
static_assert(std::atomic<int>::is_always_lock_free);

void WriteAll(const char* text) {
  std::size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<std::size_t>(n);
  }
}

// Async-signal-safe: atomics, write(2) and _exit(2) only.
void OnStopSignal(int signal) {
  int none = 0;
  const bool first = g_signal.compare_exchange_strong(none, signal);
  if (first && g_scope_depth.load() > 0) return;  // the loop stops after its current step
  WriteAll(signal == SIGINT ? "moreau: interrupted by SIGINT; no result published\n"
                            : "moreau: interrupted by SIGTERM; no result published\n");
  ::_exit(128 + signal);
}

}  // namespace

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // writes under way (HDF5) are not cut short by EINTR
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

StopScope::StopScope() { g_scope_depth.fetch_add(1); }
StopScope::~StopScope() { g_scope_depth.fetch_sub(1); }

bool StopRequested() { return g_signal.load(std::memory_order_relaxed) != 0; }

int ReportInterrupted(const std::string& message) {
  const int signal = g_signal.load();
  std::fprintf(stderr, "moreau: interrupted by %s: %s\n", signal == SIGTERM ? "SIGTERM" : "SIGINT",
               message.c_str());
  return 128 + (signal != 0 ? signal : SIGINT);
}

int RunExitCode(Termination termination, const std::string& message) {
  if (termination == Termination::kInterrupted) return ReportInterrupted(message);
  if (!IsSuccess(termination)) {
    std::fprintf(stderr, "moreau: numerical failure: %s\n", message.c_str());
    return 3;
  }
  return 0;
}

}  // namespace moreau::cli
