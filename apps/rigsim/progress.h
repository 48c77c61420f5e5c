// A one-line progress display on stderr: "label  12/40" rewritten in place on a terminal,
// printed at 25% steps otherwise (logs stay short); the stage a long run is in; and how a time
// left reads in such lines.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include <unistd.h>

namespace rigsim::cli {

// A time left for a progress line: "40 s", "12 min", "1.5 h"; "under 1 s" below a second.
inline std::string DurationInWords(double s) {
  char buf[32];
  if (s < 1) return "under 1 s";
  if (s < 90) {
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  } else if (s < 5400) {
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  }
  return buf;
}

class Progress {
 public:
  explicit Progress(std::string label) : label_(std::move(label)), tty_(::isatty(2)) {}
  void operator()(int done, int total) {
    if (tty_) {
      std::fprintf(stderr, "\r%s %d/%d", label_.c_str(), done, total);
      if (done == total) std::fprintf(stderr, "\n");
    } else if (total > 0 && (done * 4 / total != last_quarter_ || done == total)) {
      last_quarter_ = done * 4 / total;
      std::fprintf(stderr, "%s %d/%d\n", label_.c_str(), done, total);
    }
    std::fflush(stderr);
  }

 private:
  std::string label_;
  bool tty_;
  int last_quarter_ = -1;
};

// The stages of a long run as each begins, with the time since the first: "  none: placing the
// rig (at 12 s)". On a terminal one line rewritten in place and cleared by Finish, so that what
// follows starts on a clean line; otherwise a line each. Safe to call from several threads.
class StageLine {
 public:
  StageLine() : tty_(::isatty(2)), start_(std::chrono::steady_clock::now()) {}
  void operator()(const std::string& stage) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char at[48] = "";
    if (s >= 60) {
      std::snprintf(at, sizeof at, " (at %d min %02d s)", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
    } else if (s >= 1) {
      std::snprintf(at, sizeof at, " (at %.0f s)", s);
    }
    std::fprintf(stderr, tty_ ? "\r\033[K  %s%s" : "  %s%s\n", stage.c_str(), at);
    std::fflush(stderr);
    shown_ = true;
  }
  void Finish() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (tty_ && shown_) std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    shown_ = false;
  }

 private:
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  bool shown_ = false;
};

}  // namespace rigsim::cli
