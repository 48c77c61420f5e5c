#include "common/run_program.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

TEST(RunProgram, PassesArgumentsAsTheyAreAndCapturesOutput) {
  const TempDir dir;
  const fs::path log = dir / "log.txt";
  // A quote and a space in one argument reach the program unchanged: no shell in between.
  const ProgramRun run = RunProgram({"sh", "-c", "printf '%s|' \"$0\" \"$1\"; pwd", "it's a", "b c"}, log, dir);
  EXPECT_EQ(run.exit_code, 0) << run.error;
  EXPECT_EQ(ReadFile(log), "it's a|b c|" + fs::canonical(dir).string() + "\n");
}

TEST(RunProgram, AddsAndOverridesEnvironmentVariables) {
  const TempDir dir;
  setenv("RIGSIM_TEST_A", "parent", 1);
  const ProgramRun run = RunProgram({"sh", "-c", "printf '%s %s' \"$RIGSIM_TEST_A\" \"$RIGSIM_TEST_B\""}, dir / "log.txt", {},
                                    {"RIGSIM_TEST_A=child", "RIGSIM_TEST_B=new"});
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(ReadFile(dir / "log.txt"), "child new");
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
