// `--force` through the built binary: every command that writes an output folder (render,
// make-rig --out, calibrate, export, demo, sweep, report) replaces only a folder rigsim wrote, and
// refuses the user's folders, files, home and working folder and its own inputs with a message
// that says why (dataset/output_folder.h); every command that writes a single file (make-rig
// --rig-out and --frames-out, evaluate --json, generate-scene) replaces one only with --force and
// only when it is of its own kind, never an input, and never writes two outputs to one path
// (dataset/output_file.h). Each refusal leaves what was there untouched.
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
            {"demo", "--spp", "1", "--frames", "1", "--out", o, "--force"},
            {"report", Dataset().string(), "--semantics", "none", "--out", o, "--force"}};
  }

  // `args` exits 1 with an error about `folder` (as the command line names it) that says `part`.
  void ExpectRefused(const std::vector<std::string>& args, const std::string& folder, const std::string& part) {
    const CliResult r = RunRigsim(args, dir_ / ("run" + std::to_string(runs_++)));
    EXPECT_EQ(r.code, 1) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find("error: --out " + folder + ": "), std::string::npos) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find(part), std::string::npos) << args[0] << " does not say '" << part << "': " << r.err;
  }

  // `args` exits 1 with an error about the file `option` `file` that says `part`.
  void ExpectFileRefused(const std::vector<std::string>& args, const std::string& option, const fs::path& file,
                         const std::string& part) {
    const CliResult r = RunRigsim(args, dir_ / ("run" + std::to_string(runs_++)));
    EXPECT_EQ(r.code, 1) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find("error: " + option + " " + file.string() + ": "), std::string::npos) << args[0] << ": " << r.err;
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
  ExpectRefused({"report", data.string(), "--semantics", "none", "--out", data.string(), "--force"}, data.string(),
                "an input of this command (the dataset's rig.json)");
  EXPECT_TRUE(fs::exists(rig_copy / "rig.json"));
  EXPECT_TRUE(fs::exists(DatasetLayout(data).Image("cam1", "000000")));
}

TEST_F(OutputFolderCli, ForceNeverReplacesAFileOfAnotherKind) {
  const fs::path photo = dir_ / "photo.png", notes = dir_ / "thesis.tex";
  WriteFile(photo, "\x89PNG\r\n");
  WriteFile(notes, "\\chapter{1}");
  const fs::path rig = dir_ / "rig.json", frames = dir_ / "frames.json";
  for (const bool force : {false, true}) {
    const std::vector<std::string> forced = force ? std::vector<std::string>{"--force"} : std::vector<std::string>{};
    auto with = [&](std::vector<std::string> args) {
      args.insert(args.end(), forced.begin(), forced.end());
      return args;
    };
    ExpectFileRefused(with({"make-rig", "ring", "--cameras", "2", "--rig-out", photo.string(), "--frames-out", frames.string()}),
                      "--rig-out", photo, "exists and is not a JSON file, what this option writes");
    ExpectFileRefused(with({"make-rig", "ring", "--cameras", "2", "--rig-out", rig.string(), "--frames-out", notes.string()}),
                      "--frames-out", notes, "exists and is not a JSON file");
    ExpectFileRefused(with({"evaluate", Dataset().string(), Rig().string(), "--json", notes.string()}), "--json", notes,
                      "exists and is not a JSON file");
    ExpectFileRefused(with({"generate-scene", "--out", photo.string()}), "--out", photo, "exists and is not a binary glTF (.glb)");
  }
  EXPECT_EQ(ReadFile(photo), "\x89PNG\r\n");
  EXPECT_EQ(ReadFile(notes), "\\chapter{1}");
  EXPECT_FALSE(fs::exists(rig));
  EXPECT_FALSE(fs::exists(frames));
}

TEST_F(OutputFolderCli, AFileOfItsOwnKindIsReplacedOnlyWithForce) {
  const fs::path rig = dir_ / "rig.json", frames = dir_ / "frames.json", scores = dir_ / "scores.json";
  const std::vector<std::string> make_rig = {"make-rig", "ring", "--cameras", "2", "--rig-out", rig.string(), "--frames-out",
                                             frames.string()};
  ASSERT_EQ(RunRigsim(make_rig, dir_ / "first").code, 0);
  const std::string first = ReadFile(rig);
  std::vector<std::string> three = make_rig;
  three[3] = "3";
  ExpectFileRefused(three, "--rig-out", rig, "already exists (use --force to replace it)");
  EXPECT_EQ(ReadFile(rig), first);
  three.push_back("--force");
  const CliResult replaced = RunRigsim(three, dir_ / "replaced");
  EXPECT_EQ(replaced.code, 0) << replaced.err;
  EXPECT_NE(ReadFile(rig), first);

  const std::vector<std::string> evaluate = {"evaluate", Dataset().string(), Rig().string(), "--json", scores.string()};
  ASSERT_EQ(RunRigsim(evaluate, dir_ / "scores").code, 0);
  ExpectFileRefused(evaluate, "--json", scores, "already exists (use --force to replace it)");
  std::vector<std::string> forced = evaluate;
  forced.push_back("--force");
  EXPECT_EQ(RunRigsim(forced, dir_ / "scores-forced").code, 0);
}

TEST_F(OutputFolderCli, ForceNeverReplacesAFileTheCommandReads) {
  const fs::path data = dir_ / "dataset";
  fs::copy(Dataset(), data, fs::copy_options::recursive);
  const std::string truth = ReadFile(data / "rig.json");
  ExpectFileRefused({"evaluate", data.string(), (data / "rig.json").string(), "--json", (data / "rig.json").string(), "--force"},
                    "--json", data / "rig.json", "an input of this command (the dataset's rig.json)");
  // A calibration folder is read whole: no file in it is replaced.
  const fs::path estimate = dir_ / "estimate";
  fs::create_directories(estimate / "none");
  WriteFile(estimate / "evaluation.json", R"({"methods": {"none": {}}})");
  fs::copy_file(data / "rig.json", estimate / "none" / "rig.json");
  ExpectFileRefused({"evaluate", data.string(), estimate.string(), "--json", (estimate / "evaluation.json").string(), "--force"},
                    "--json", estimate / "evaluation.json", "lies inside " + estimate.string() + ", an input of this command (ESTIMATE)");
  ExpectFileRefused({"make-rig", "file", "--rig-file", (data / "rig.json").string(), "--rig-out", (data / "rig.json").string(),
                     "--frames-out", (dir_ / "frames.json").string(), "--force"},
                    "--rig-out", data / "rig.json", "an input of this command (--rig-file)");
  EXPECT_EQ(ReadFile(data / "rig.json"), truth);
  EXPECT_EQ(ReadFile(estimate / "evaluation.json"), R"({"methods": {"none": {}}})");
}

// A file whose folder does not exist is refused before the work, so that no other output of
// the command is written without it.
TEST_F(OutputFolderCli, AFileInAFolderThatDoesNotExistIsRefusedFirst) {
  const fs::path rig = dir_ / "rig.json", frames = dir_ / "nowhere" / "frames.json";
  ExpectFileRefused({"make-rig", "ring", "--cameras", "2", "--rig-out", rig.string(), "--frames-out", frames.string()},
                    "--frames-out", frames, "its folder " + (dir_ / "nowhere").string() + " does not exist");
  EXPECT_FALSE(fs::exists(rig));
  ExpectFileRefused({"generate-scene", "--out", (dir_ / "nowhere" / "s.glb").string()}, "--out", dir_ / "nowhere" / "s.glb",
                    "does not exist");
}

TEST_F(OutputFolderCli, TwoOutputsOfOneCommandAreNeverOneFile) {
  const fs::path same = dir_ / "rig.json";
  for (const std::string& second : {same.string(), (dir_ / "." / "rig.json").string()}) {
    const CliResult r = RunRigsim({"make-rig", "ring", "--cameras", "2", "--rig-out", same.string(), "--frames-out", second, "--force"},
                                  dir_ / ("same" + std::to_string(runs_++)));
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("error: --rig-out and --frames-out are both " + second + ": "), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(same));
  }
}

}  // namespace
}  // namespace rigsim
