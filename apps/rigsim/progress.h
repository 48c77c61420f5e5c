// What a long run shows on stderr while it works: one line rewritten in place on a terminal, and
// only the lines that matter in a log (so logs stay short). A count ("rendering views 12/40"), the
// stage a run is in ("  none: placing the rig (at 12 s)"), and how a time left reads in such lines.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include <unistd.h>

#include "common/format.h"

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

// The one line on stderr that every display below writes through. On a terminal each Show
// replaces the line; otherwise a Show prints a line of its own only when it is a milestone. Safe
// to call from several threads.
class LiveLine {
 public:
  LiveLine() : tty_(::isatty(2)) {}
  bool OnTerminal() const { return tty_; }
  void Show(const std::string& text, bool milestone) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (tty_) {
      std::fprintf(stderr, "\r\033[K%s", text.c_str());
      shown_ = true;
    } else if (milestone) {
      std::fprintf(stderr, "%s\n", text.c_str());
    }
    std::fflush(stderr);
  }
  // On a terminal, ends the line shown: `keep` leaves it (a newline), otherwise it is cleared, so
  // that what follows starts on a clean line.
  void Finish(bool keep) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (tty_ && shown_) std::fprintf(stderr, keep ? "\n" : "\r\033[K");
    std::fflush(stderr);
    shown_ = false;
  }

 private:
  bool tty_;
  std::mutex mutex_;
  bool shown_ = false;
};

// A count: "label 12/40" (with `unit`, "label 12/40 views"), then `detail`; in a log at each
// quarter and at the end. The line stays when the count is done.
class Progress {
 public:
  explicit Progress(std::string label, std::string unit = "") : label_(std::move(label)), unit_(std::move(unit)) {}
  void operator()(int done, int total, const std::string& detail = "") {
    const int quarter = total > 0 ? done * 4 / total : 0;
    std::string text = label_ + " " + std::to_string(done) + "/" + (unit_.empty() ? std::to_string(total) : Count(total, unit_));
    line_.Show(text + detail, total > 0 && (quarter != last_quarter_ || done == total));
    last_quarter_ = quarter;
    if (done == total) line_.Finish(true);
  }

 private:
  std::string label_, unit_;
  LiveLine line_;
  int last_quarter_ = -1;
};

// The stages of a long run as each begins, with the time since the first: "  none: placing the
// rig (at 12 s)"; a line each in a log. Finish clears it from a terminal.
class StageLine {
 public:
  StageLine() : start_(std::chrono::steady_clock::now()) {}
  void operator()(const std::string& stage) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char at[48] = "";
    if (s >= 60) {
      std::snprintf(at, sizeof at, " (at %d min %02d s)", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
    } else if (s >= 1) {
      std::snprintf(at, sizeof at, " (at %.0f s)", s);
    }
    line_.Show("  " + stage + at, true);
  }
  void Finish() { line_.Finish(false); }

 private:
  std::chrono::steady_clock::time_point start_;
  LiveLine line_;
};

}  // namespace rigsim::cli
