// `--force` through the built binary: every command that writes an output folder (render,
// make-rig --out, calibrate, export, demo, sweep) replaces only a folder rigsim wrote, and refuses
// the user's folders, files, home and working folder and its own inputs with a message that says
// why (dataset/output_folder.h). Each refusal leaves what was there untouched.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

const std::string kStreet = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";

class OutputFolderCli : public testing::Test {
 protected:
  // A tiny rig and a dataset rendered from it, shared by the tests (none of them changes it).
  static void SetUpTestSuite() {
    base_ = new fs::path(fs::temp_directory_path() / ("rigsim_output_folder_cli_" + std::to_string(::getpid())));
    fs::remove_all(*base_);
    fs::create_directories(*base_);
    ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "2", "--width", "64", "--height", "48", "--frames", "1", "--out",
                         (*base_ / "rig").string()},
                        *base_ / "make-rig")
                  .code,
              0);
    const CliResult r = RunRigsim({"render", "--scene", kStreet, "--rig", (*base_ / "rig" / "rig.json").string(), "--frames",
                                   (*base_ / "rig" / "frames.json").string(), "--out", (*base_ / "dataset").string(), "--spp",
                                   "1"},
                                  *base_ / "render");
    ASSERT_EQ(r.code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*base_);
    delete base_;
  }

  void SetUp() override { dir_ = temp_.path(); }

  static fs::path Rig() { return *base_ / "rig" / "rig.json"; }
  static fs::path Frames() { return *base_ / "rig" / "frames.json"; }
  static fs::path Dataset() { return *base_ / "dataset"; }

  // Every command that writes a folder, writing `out` with --force.
  std::vector<std::vector<std::string>> EveryCommandInto(const fs::path& out) const {
    const std::string o = out.string();
    return {{"render", "--scene", kStreet, "--rig", Rig().string(), "--frames", Frames().string(), "--out", o, "--spp", "1", "--force"},
            {"make-rig", "ring", "--cameras", "2", "--out", o, "--force"},
            {"calibrate", Dataset().string(), "--semantics", "none", "--out", o, "--force"},
            {"export", Dataset().string(), "--format", "kalibr", "--out", o, "--force"},
            {"demo", "--spp", "1", "--frames", "1", "--out", o, "--force"}};
  }

  // `args` exits 1 with an error about `folder` (as the command line names it) that says `part`.
  void ExpectRefused(const std::vector<std::string>& args, const std::string& folder, const std::string& part) {
    const CliResult r = RunRigsim(args, dir_ / ("run" + std::to_string(runs_++)));
    EXPECT_EQ(r.code, 1) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find("error: --out " + folder + ": "), std::string::npos) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find(part), std::string::npos) << args[0] << " does not say '" << part << "': " << r.err;
  }

  static fs::path* base_;
  const TempDir temp_;
  fs::path dir_;
  int runs_ = 0;
};
fs::path* OutputFolderCli::base_ = nullptr;

TEST_F(OutputFolderCli, ForceNeverReplacesAFolderOfOtherFiles) {
  const fs::path work = dir_ / "thesis";
  fs::create_directories(work / "src");
  std::ofstream(work / "src" / "thesis.tex") << "chapter 1";
  for (const auto& args : EveryCommandInto(work)) {
    ExpectRefused(args, work.string(), "holds files that rigsim did not write (it has no .rigsim-output)");
  }
  std::ofstream(dir_ / "tiny.yaml") << "name: tiny\nbase: {rig: ring, cameras: 2, width: 64, height: 48, frames: 1, spp: 1}\n"
                                       "methods: {semantics: [none]}\ngrid:\n  radius: [0.3, 0.6]\n";
  ExpectRefused({"sweep", (dir_ / "tiny.yaml").string(), "--out", work.string(), "--force"}, work.string(),
                "holds files that rigsim did not write");
  EXPECT_EQ(ReadFile(work / "src" / "thesis.tex"), "chapter 1");
  EXPECT_TRUE(StagingFolders(work).empty());
}

TEST_F(OutputFolderCli, ForceNeverReplacesAFile) {
  std::ofstream(dir_ / "notes.txt") << "mine";
  for (const auto& args : EveryCommandInto(dir_ / "notes.txt")) {
    ExpectRefused(args, (dir_ / "notes.txt").string(), "is a file, not a folder");
  }
  EXPECT_EQ(ReadFile(dir_ / "notes.txt"), "mine");
}

TEST_F(OutputFolderCli, ForceReplacesOnlyWhatRigsimWrote) {
  const fs::path out = dir_ / "rig";
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "2", "--out", out.string()}, dir_ / "first").code, 0);
  EXPECT_NE(ReadFile(out / ".rigsim-output").find("\"written_by\": \"rigsim make-rig\""), std::string::npos);
  const CliResult again = RunRigsim({"make-rig", "ring", "--cameras", "3", "--out", out.string(), "--force"}, dir_ / "again");
  EXPECT_EQ(again.code, 0) << again.err;
  // A file added to rigsim's folder is the user's: the folder is not replaced any more.
  std::ofstream(out / "notes.txt") << "mine";
  ExpectRefused({"make-rig", "ring", "--cameras", "2", "--out", out.string(), "--force"}, out.string(),
                "holds notes.txt, which rigsim did not write there");
  EXPECT_EQ(ReadFile(out / "notes.txt"), "mine");
}

TEST_F(OutputFolderCli, ForceNeverReplacesTheHomeOrTheWorkingFolder) {
  // A home folder and a working folder that rigsim wrote (the worst case: their marker says so).
  const fs::path home = dir_ / "home";
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--out", home.string()}, dir_ / "home-rig").code, 0);
  const char* old_home = std::getenv("HOME");
  const std::string saved = old_home ? old_home : "";
  ::setenv("HOME", home.c_str(), 1);
  ExpectRefused({"make-rig", "ring", "--out", home.string(), "--force"}, home.string(), "is your home folder");
  ExpectRefused({"make-rig", "ring", "--out", dir_.string(), "--force"}, dir_.string(), "holds your home folder");
  if (old_home) ::setenv("HOME", saved.c_str(), 1); else ::unsetenv("HOME");

  const fs::path work = dir_ / "work";
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--out", work.string()}, dir_ / "work-rig").code, 0);
  const fs::path cwd = fs::current_path();
  fs::current_path(work);
  ExpectRefused({"make-rig", "ring", "--out", ".", "--force"}, ".", "is the working folder");
  fs::current_path(cwd);
  EXPECT_TRUE(fs::exists(home / "rig.json"));
  EXPECT_TRUE(fs::exists(work / "rig.json"));
}

TEST_F(OutputFolderCli, ForceNeverReplacesAnInputOfTheSameCommand) {
  // The rig folder (rigsim's) holds render's --rig and --frames.
  const fs::path rig_copy = dir_ / "rig";
  fs::copy(*base_ / "rig", rig_copy, fs::copy_options::recursive);
  ExpectRefused({"render", "--scene", kStreet, "--rig", (rig_copy / "rig.json").string(), "--frames",
                 (rig_copy / "frames.json").string(), "--out", rig_copy.string(), "--force"},
                rig_copy.string(), "holds " + (rig_copy / "rig.json").string() + ", an input of this command (--rig)");
  // calibrate and export into the dataset they read, or into its photos.
  const fs::path data = dir_ / "dataset";
  fs::copy(Dataset(), data, fs::copy_options::recursive);
  ExpectRefused({"calibrate", data.string(), "--semantics", "none", "--out", data.string(), "--force"}, data.string(),
                "an input of this command (the dataset's rig.json)");
  ExpectRefused({"calibrate", data.string(), "--semantics", "none", "--out", (data / "images").string(), "--force"},
                (data / "images").string(), "an input of this command (the dataset's images/)");
  ExpectRefused({"export", data.string(), "--format", "kalibr", "--out", data.string(), "--force"}, data.string(),
                "an input of this command");
  EXPECT_TRUE(fs::exists(rig_copy / "rig.json"));
  EXPECT_TRUE(fs::exists(DatasetLayout(data).Image("cam1", "000000")));
}

}  // namespace
}  // namespace rigsim
