// Runs another program (gnuplot, COLMAP) without a shell: arguments are passed as they are, so
// paths with spaces or quotes need no escaping.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rigsim {

// The program's path when `name` is found on the PATH (or is a path to an executable file);
// empty otherwise.
std::string FindProgram(const std::string& name);

struct ProgramRun {
  int exit_code = -1;  // the program's exit status; 128 + N when killed by signal N; -1 when it could not start
  std::string error;   // why it could not start
};

// Runs argv[0] with its arguments in `working_dir` (the current folder when empty), standard
// output and error appended to `log_file` (discarded when empty), with this process's environment
// plus `environment` ("NAME=value" entries, which win), and waits for it.
ProgramRun RunProgram(const std::vector<std::string>& argv, const std::filesystem::path& log_file = {},
                      const std::filesystem::path& working_dir = {}, const std::vector<std::string>& environment = {});

}  // namespace rigsim
