// A one-line progress display on stderr: "label  12/40" rewritten in place on a terminal,
// printed at 25% steps otherwise (logs stay short); and how a time left reads in such lines.
#pragma once

#include <cstdio>
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

}  // namespace rigsim::cli
