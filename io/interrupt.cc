#include "io/interrupt.h"

#include <unistd.h>

#include <csignal>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace axis {
namespace {

// The messages are formatted in advance: a handler may only call
// async-signal-safe functions (write, _exit), POSIX.1-2017 §2.4.3.
constexpr size_t kMessageSize = 4096;
char g_program[256] = "program";
char g_nothing[2][kMessageSize];    // [0] SIGINT, [1] SIGTERM
char g_after[2][kMessageSize];
volatile std::sig_atomic_t g_deferred = 0;
volatile std::sig_atomic_t g_pending = 0;

void Format(const std::string& path) {
  const char* names[2] = {"SIGINT", "SIGTERM"};
  for (int k = 0; k < 2; ++k) {
    std::string nothing = std::string(g_program) + ": interrupted by " + names[k] +
                          ": nothing written" + (path.empty() ? "" : " to " + path) + "\n";
    std::string after = std::string(g_program) + ": interrupted by " + names[k] + " after " +
                        (path.empty() ? std::string("the output") : path) +
                        " was written\n";
    nothing.resize(std::min(nothing.size(), kMessageSize - 1));
    after.resize(std::min(after.size(), kMessageSize - 1));
    std::memcpy(g_nothing[k], nothing.c_str(), nothing.size() + 1);
    std::memcpy(g_after[k], after.c_str(), after.size() + 1);
  }
}

void Report(const char* message, int signal) {
  const ssize_t ignored = ::write(STDERR_FILENO, message, std::strlen(message));
  (void)ignored;
  ::_exit(128 + signal);
}

extern "C" void HandleInterrupt(int signal) {
  if (g_deferred) {
    g_pending = signal;
    return;
  }
  Report(g_nothing[signal == SIGINT ? 0 : 1], signal);
}

}  // namespace

void InstallInterruptHandlers(const std::string& program) {
  const size_t n = std::min(program.size(), sizeof(g_program) - 1);
  std::memcpy(g_program, program.data(), n);
  g_program[n] = '\0';
  Format("");
  struct sigaction action {};
  action.sa_handler = HandleInterrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  for (int signal : {SIGINT, SIGTERM}) {
    if (::sigaction(signal, &action, nullptr) != 0) {
      throw std::runtime_error(program + ": cannot install the handler of signal " +
                               std::to_string(signal) + ": " + std::strerror(errno));
    }
  }
}

void SetInterruptTarget(const std::string& path) { Format(path); }

namespace {
bool g_committed = false;
}  // namespace

DeferInterrupts::DeferInterrupts() {
  g_committed = false;
  g_deferred = 1;
}

void DeferInterrupts::Committed() { g_committed = true; }

DeferInterrupts::~DeferInterrupts() {
  g_deferred = 0;
  const int signal = g_pending;
  if (signal != 0) {
    Report((g_committed ? g_after : g_nothing)[signal == SIGINT ? 0 : 1], signal);
  }
}

}  // namespace axis
