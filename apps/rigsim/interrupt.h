// Ctrl-C during a long write: the first SIGINT (or SIGTERM) only sets a flag, which the progress
// callback turns into an Interrupted exception, so the stack unwinds and StagedOutput removes its
// staging folder; a second signal terminates at once (the handler is one-shot). A SIGKILL cannot
// be caught: its staging folder is removed by the next run (dataset/dataset.h StagedOutput).
#pragma once

#include <csignal>
#include <stdexcept>
#include <string>

namespace rigsim::cli {

// Thrown by InterruptScope::ThrowIfRequested; main() exits with 128 + signal.
struct Interrupted : std::runtime_error {
  explicit Interrupted(int sig)
      : std::runtime_error(std::string("interrupted by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM") +
                           "; the output was not written"),
        signal(sig) {}
  int signal;
};

// Installs the handlers for its lifetime.
class InterruptScope {
 public:
  InterruptScope() {
    requested_ = 0;
    struct sigaction sa = {};
    sa.sa_handler = &InterruptScope::Handle;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;  // the next signal gets the default action: terminate
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~InterruptScope() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

  static void ThrowIfRequested() {
    if (requested_ != 0) throw Interrupted(requested_);
  }

 private:
  static void Handle(int sig) { requested_ = sig; }
  static inline volatile std::sig_atomic_t requested_ = 0;
  struct sigaction old_int_ = {}, old_term_ = {};
};

}  // namespace rigsim::cli
