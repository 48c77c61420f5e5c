#include "common/run_program.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

namespace rigsim {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("rigsim_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(RunProgram, PassesArgumentsAsTheyAreAndCapturesOutput) {
  const fs::path dir = TempDir("run_program");
  const fs::path log = dir / "log.txt";
  // A quote and a space in one argument reach the program unchanged: no shell in between.
  const ProgramRun run = RunProgram({"sh", "-c", "printf '%s|' \"$0\" \"$1\"; pwd", "it's a", "b c"}, log, dir);
  EXPECT_EQ(run.exit_code, 0) << run.error;
  EXPECT_EQ(Read(log), "it's a|b c|" + fs::canonical(dir).string() + "\n");
  fs::remove_all(dir);
}

TEST(RunProgram, AddsAndOverridesEnvironmentVariables) {
  const fs::path dir = TempDir("run_program_env");
  setenv("RIGSIM_TEST_A", "parent", 1);
  const ProgramRun run = RunProgram({"sh", "-c", "printf '%s %s' \"$RIGSIM_TEST_A\" \"$RIGSIM_TEST_B\""}, dir / "log.txt", {},
                                    {"RIGSIM_TEST_A=child", "RIGSIM_TEST_B=new"});
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(Read(dir / "log.txt"), "child new");
  fs::remove_all(dir);
}

TEST(RunProgram, ReportsExitCodesAndMissingPrograms) {
  EXPECT_EQ(RunProgram({"sh", "-c", "exit 7"}).exit_code, 7);
  const ProgramRun missing = RunProgram({"rigsim-no-such-program"});
  EXPECT_EQ(missing.exit_code, -1);
  EXPECT_NE(missing.error.find("rigsim-no-such-program is not installed"), std::string::npos);
  EXPECT_EQ(FindProgram("rigsim-no-such-program"), "");
  EXPECT_NE(FindProgram("sh"), "");
}

}  // namespace
}  // namespace rigsim
