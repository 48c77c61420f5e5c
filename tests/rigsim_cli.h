// Running the built rigsim binary from a test: the one copy of the fork/exec/capture code that the
// command-line tests share. Compiled into each such test, whose target defines RIGSIM_BINARY.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "testing/temp_dir.h"

namespace rigsim {

// rigsim started with `args` (no shell involved); stdout and stderr go to the files
// `log_prefix`.stdout and .stderr. For tests that signal the running process.
class RigsimProcess {
 public:
  RigsimProcess(const std::vector<std::string>& args, const std::filesystem::path& log_prefix);
  pid_t pid() const { return pid_; }
  // Waits (at most `timeout`, then kills it and fails the test); the exit code, or 128 + signal.
  int Wait(std::chrono::seconds timeout = std::chrono::seconds(120));
  std::string out() const { return ReadFile(out_); }
  std::string err() const { return ReadFile(err_); }

 private:
  pid_t pid_ = -1;
  std::filesystem::path out_, err_;
};

struct CliResult {
  int code = -1;  // exit code, or 128 + signal
  std::string out, err;
};

// Runs rigsim to the end (RigsimProcess, then Wait).
CliResult RunRigsim(const std::vector<std::string>& args, const std::filesystem::path& log_prefix,
                    std::chrono::seconds timeout = std::chrono::seconds(120));

// The hidden staging folders ".NAME.partial-*" that a run writing to `out` builds beside it
// (dataset/dataset.h StagedOutput); after any run, finished or failed, there should be none.
std::vector<std::filesystem::path> StagingFolders(const std::filesystem::path& out);

}  // namespace rigsim
