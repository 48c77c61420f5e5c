#include "tests/rigsim_cli.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <thread>

#include <gtest/gtest.h>

#ifndef RIGSIM_BINARY
#error "RIGSIM_BINARY must name the rigsim executable"
#endif

namespace rigsim {

RigsimProcess::RigsimProcess(const std::vector<std::string>& args, const std::filesystem::path& log_prefix)
    : out_(log_prefix.string() + ".stdout"), err_(log_prefix.string() + ".stderr") {
  pid_ = fork();
  if (pid_ == 0) {
    const int out = ::open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(out, 1);
    dup2(err, 2);
    std::vector<std::string> copy = args;
    std::string binary = RIGSIM_BINARY;
    std::vector<char*> argv = {binary.data()};
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
}

int RigsimProcess::Wait(std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (waitpid(pid_, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
      ADD_FAILURE() << "rigsim did not finish in " << timeout.count() << " s";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

CliResult RunRigsim(const std::vector<std::string>& args, const std::filesystem::path& log_prefix,
                    std::chrono::seconds timeout) {
  RigsimProcess process(args, log_prefix);
  CliResult r;
  r.code = process.Wait(timeout);
  r.out = process.out();
  r.err = process.err();
  return r;
}

std::vector<std::filesystem::path> StagingFolders(const std::filesystem::path& out) {
  std::vector<std::filesystem::path> found;
  std::string prefix = ".";  // (built with += : GCC 12 warns falsely on "." + s + "...")
  prefix += out.filename().string();
  prefix += ".partial-";
  if (!std::filesystem::exists(out.parent_path())) return found;
  for (const auto& e : std::filesystem::directory_iterator(out.parent_path())) {
    if (e.path().filename().string().rfind(prefix, 0) == 0) found.push_back(e.path());
  }
  return found;
}

}  // namespace rigsim
