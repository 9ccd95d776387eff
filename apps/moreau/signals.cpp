#include "signals.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace moreau::cli {
namespace {

std::atomic<int> g_scope_depth{0};  // live StopScopes
std::atomic<bool> g_quiet{false};   // QuietStopMessages
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free);

void WriteAll(const char* text) {
  if (g_quiet.load()) return;
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
  const bool first = RequestStop(signal);
  if (first && g_scope_depth.load() > 0) return;  // the loops stop at their next poll
  if (first) {
    WriteAll(signal == SIGINT ? "moreau: interrupted by SIGINT; no result published\n"
                              : "moreau: interrupted by SIGTERM; no result published\n");
  } else {
    WriteAll(signal == SIGINT ? "moreau: interrupted by SIGINT again; stopped at once\n"
                              : "moreau: interrupted by SIGTERM again; stopped at once\n");
  }
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

int RunStoppable(const std::function<int()>& run) {
  const StopScope stop_on_signal;
  int code = 0;
  try {
    code = run();
  } catch (const Interrupted& e) {
    return ReportInterrupted(std::string(e.what()) + "; no result published");
  }
  if (code == 0 && StopRequested()) {
    return ReportInterrupted("the result was complete and is published");
  }
  return code;
}

void QuietStopMessages() { g_quiet.store(true); }

int ReportInterrupted(const std::string& message) {
  const int signal = StopReason();
  if (!g_quiet.load()) {
    std::fprintf(stderr, "moreau: interrupted by %s: %s\n",
                 signal == SIGTERM ? "SIGTERM" : "SIGINT", message.c_str());
  }
  return 128 + (signal == SIGINT || signal == SIGTERM ? signal : SIGINT);
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
