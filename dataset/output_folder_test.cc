#include "dataset/output_folder.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>

#include <gtest/gtest.h>

#include "dataset/output_file.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("rigsim_output_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Touch(const fs::path& p, const std::string& text = "x") {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

std::string ReadText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

OutputFolderRequest Request(const fs::path& dir, bool force = false) {
  OutputFolderRequest r;
  r.dir = dir;
  r.force = force;
  r.written_by = "rigsim test";
  return r;
}

// `request` is refused with a message that starts with "--out DIR: " and says `part`.
void ExpectRefused(const OutputFolderRequest& request, const std::string& part) {
  try {
    CheckOutputFolder(request);
    ADD_FAILURE() << request.dir << " was not refused";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("--out " + request.dir.string() + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(part), std::string::npos) << "does not say '" << part << "': " << what;
  }
  // StagedOutput refuses it too, with --force, and leaves what is there as it was.
  OutputFolderRequest forced = request;
  forced.force = true;
  EXPECT_THROW(StagedOutput{forced}, std::runtime_error) << request.dir;
}

// Writes `files` into a new output folder `out` through StagedOutput.
void WriteOutput(const fs::path& out, const std::vector<std::string>& files, bool force = false) {
  StagedOutput staged(Request(out, force));
  for (const std::string& f : files) Touch(staged.staging_dir() / f);
  staged.Commit();
}

// Sets an environment variable for the scope of one test.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// Changes the working folder for the scope of one test.
class ScopedCwd {
 public:
  explicit ScopedCwd(const fs::path& dir) : old_(fs::current_path()) { fs::current_path(dir); }
  ~ScopedCwd() { fs::current_path(old_); }

 private:
  fs::path old_;
};

TEST(StagedOutput, NothingAppearsUntilCommitAndFailuresLeaveNothing) {
  const fs::path dir = FreshDir("staged");
  const fs::path out = dir / "out";
  {
    StagedOutput staged(out, false);
    Touch(staged.staging_dir() / "file");
    EXPECT_FALSE(fs::exists(out));
  }  // not committed: as if interrupted
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(dir));
  WriteOutput(out, {"file"});
  EXPECT_TRUE(fs::exists(out / "file"));
  EXPECT_THROW(StagedOutput(out, false), std::runtime_error);  // no overwrite without force
  {
    StagedOutput staged(out, true);
    Touch(staged.staging_dir() / "other");
    EXPECT_TRUE(fs::exists(out / "file"));  // old output intact until commit
    staged.Commit();
  }
  EXPECT_FALSE(fs::exists(out / "file"));
  EXPECT_TRUE(fs::exists(out / "other"));
  fs::remove_all(dir);
}

TEST(OutputFolder, EveryOutputCarriesAMarkerListingWhatRigsimWrote) {
  const fs::path dir = FreshDir("marker");
  WriteOutput(dir / "out", {"rig.json", "images/cam0/0001.png"});
  std::ifstream in(dir / "out" / kOutputMarker);
  const std::string marker((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(marker.find("\"written_by\": \"rigsim test\""), std::string::npos) << marker;
  EXPECT_NE(marker.find("\"images\""), std::string::npos) << marker;
  EXPECT_NE(marker.find("\"rig.json\""), std::string::npos) << marker;
  const OutputFolderState state = CheckOutputFolder(Request(dir / "out"));
  EXPECT_EQ(state.kind, OutputFolderState::kWrittenByRigsim);
  EXPECT_EQ(state.written_by, "rigsim test");
  fs::remove_all(dir);
}

TEST(OutputFolder, NewAndEmptyFoldersAreWrittenWithoutForce) {
  const fs::path dir = FreshDir("new");
  EXPECT_EQ(CheckOutputFolder(Request(dir / "a" / "b")).kind, OutputFolderState::kAbsent);
  fs::create_directories(dir / "empty");
  EXPECT_EQ(CheckOutputFolder(Request(dir / "empty")).kind, OutputFolderState::kEmpty);
  WriteOutput(dir / "empty", {"x"});  // nothing there to lose: no --force needed
  EXPECT_TRUE(fs::exists(dir / "empty" / "x"));
  fs::remove_all(dir);
}

TEST(OutputFolder, AFolderOfOtherFilesIsNeverReplaced) {
  const fs::path dir = FreshDir("foreign");
  Touch(dir / "thesis" / "src" / "thesis.tex");
  ExpectRefused(Request(dir / "thesis"), "holds files that rigsim did not write (it has no .rigsim-output)");
  EXPECT_TRUE(fs::exists(dir / "thesis" / "src" / "thesis.tex"));
  fs::remove_all(dir);
}

TEST(OutputFolder, FilesAddedToARigsimOutputAreNeverReplaced) {
  const fs::path dir = FreshDir("added");
  WriteOutput(dir / "out", {"rig.json"});
  Touch(dir / "out" / "notes.txt");
  ExpectRefused(Request(dir / "out"), "holds notes.txt, which rigsim did not write there");
  EXPECT_TRUE(fs::exists(dir / "out" / "notes.txt"));
  // An output of rigsim's own inside (calibrate's DATASET/calibration) is rigsim's.
  fs::remove(dir / "out" / "notes.txt");
  WriteOutput(dir / "out" / "calibration", {"evaluation.json"});
  EXPECT_EQ(CheckOutputFolder(Request(dir / "out")).kind, OutputFolderState::kWrittenByRigsim);
  WriteOutput(dir / "out", {"rig.json"}, /*force=*/true);
  EXPECT_FALSE(fs::exists(dir / "out" / "calibration"));
  fs::remove_all(dir);
}

TEST(OutputFolder, AFileIsRefused) {
  const fs::path dir = FreshDir("file");
  Touch(dir / "thesis.tex", "precious");
  ExpectRefused(Request(dir / "thesis.tex"), "is a file, not a folder");
  std::ifstream in(dir / "thesis.tex");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "precious");
  fs::remove_all(dir);
}

TEST(OutputFolder, TheRootIsRefused) { ExpectRefused(Request("/"), "is the root folder"); }

TEST(OutputFolder, TheHomeFolderAndItsAncestorsAreRefused) {
  const fs::path dir = FreshDir("home");
  WriteOutput(dir / "me", {"rig.json"});  // even a home folder that looks like rigsim's
  const ScopedEnv home("HOME", (dir / "me").string());
  ExpectRefused(Request(dir / "me"), "is your home folder");
  ExpectRefused(Request(dir), "holds your home folder");
  fs::remove_all(dir);
}

TEST(OutputFolder, TheWorkingFolderAndItsAncestorsAreRefused) {
  const fs::path dir = FreshDir("cwd");
  WriteOutput(dir / "out", {"images/cam0/0001.png"});
  {
    const ScopedCwd cwd(dir / "out" / "images");
    ExpectRefused(Request("."), "is the working folder");
    ExpectRefused(Request(".."), "holds the working folder");
    ExpectRefused(Request(dir / "out"), "holds the working folder");
  }
  EXPECT_TRUE(fs::exists(dir / "out" / "images" / "cam0" / "0001.png"));
  fs::remove_all(dir);
}

TEST(OutputFolder, AFolderThatHoldsAnInputOfTheCommandIsRefused) {
  const fs::path dir = FreshDir("input");
  WriteOutput(dir / "dataset", {"rig.json", "images/cam0/0001.png"});
  OutputFolderRequest r = Request(dir / "dataset");
  r.inputs = {{dir / "dataset" / "rig.json", "--rig"}};
  ExpectRefused(r, "holds " + (dir / "dataset" / "rig.json").string() + ", an input of this command (--rig)");
  r.inputs = {{dir / "dataset" / "images", "the dataset's images/"}};
  ExpectRefused(r, "an input of this command (the dataset's images/)");
  r.dir = dir / "dataset" / "images";
  ExpectRefused(r, "is " + (dir / "dataset" / "images").string() + ", an input");
  r.dir = dir / "dataset" / "images" / "cam0";
  ExpectRefused(r, "lies inside " + (dir / "dataset" / "images").string());
  // Beside the inputs is fine: calibrate's DATASET/calibration.
  r.dir = dir / "dataset" / "calibration";
  EXPECT_EQ(CheckOutputFolder(r).kind, OutputFolderState::kAbsent);
  EXPECT_TRUE(fs::exists(dir / "dataset" / "images" / "cam0" / "0001.png"));
  fs::remove_all(dir);
}

TEST(OutputFolder, AMessageNamesTheDefaultFolderWithoutAnOption) {
  const fs::path dir = FreshDir("default");
  Touch(dir / "calibration" / "mine.txt");
  OutputFolderRequest r = Request(dir / "calibration");
  r.option = "";
  try {
    CheckOutputFolder(r);
    FAIL() << "not refused";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind((dir / "calibration").string() + ": exists and holds files", 0), 0u) << what;
    EXPECT_NE(what.find("choose another folder with --out"), std::string::npos) << what;
  }
  fs::remove_all(dir);
}

// `request` is refused with a message that starts with "OPTION FILE: " and says `part`, with or
// without --force.
void ExpectFileRefused(OutputFileRequest request, const std::string& part) {
  for (const bool force : {false, true}) {
    request.force = force;
    try {
      CheckReplaceableFile(request);
      ADD_FAILURE() << request.file << " was not refused (force " << force << ")";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(request.option + " " + request.file.string() + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(part), std::string::npos) << "does not say '" << part << "': " << what;
    }
  }
}

TEST(OutputFile, ANewFileIsWrittenAndAnExistingOneOfItsKindOnlyWithForce) {
  const fs::path dir = FreshDir("file_force");
  OutputFileRequest r{dir / "rig.json", "--rig-out", OutputFileKind::kJson, {}, false};
  EXPECT_NO_THROW(CheckReplaceableFile(r));
  Touch(dir / "rig.json", " \n{\"cameras\": []}");
  try {
    CheckReplaceableFile(r);
    ADD_FAILURE() << "not refused without --force";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "--rig-out " + (dir / "rig.json").string() + ": already exists (use --force to replace it)");
  }
  r.force = true;
  EXPECT_NO_THROW(CheckReplaceableFile(r));
  Touch(dir / "street.glb", std::string("glTF\x02\0\0\0", 8));
  EXPECT_NO_THROW(CheckReplaceableFile({dir / "street.glb", "--out", OutputFileKind::kGlb, {}, true}));
  fs::remove_all(dir);
}

TEST(OutputFile, ForceNeverReplacesAFileOfAnotherKindAFolderOrAnInput) {
  const fs::path dir = FreshDir("file_refused");
  Touch(dir / "thesis.tex", "\\chapter{1}");
  Touch(dir / "photo.png", "\x89PNG");
  ExpectFileRefused({dir / "thesis.tex", "--rig-out", OutputFileKind::kJson, {}, false}, "is not a JSON file");
  ExpectFileRefused({dir / "photo.png", "--out", OutputFileKind::kGlb, {}, false}, "is not a binary glTF (.glb)");
  ExpectFileRefused({dir, "--json", OutputFileKind::kJson, {}, false}, "is a folder, not a file");
  ExpectFileRefused({dir / "nowhere" / "scores.json", "--json", OutputFileKind::kJson, {}, false},
                    "its folder " + (dir / "nowhere").string() + " does not exist");
  Touch(dir / "dataset" / "rig.json", "{}");
  Touch(dir / "calibration" / "none" / "rig.json", "{}");
  ExpectFileRefused({dir / "dataset" / "rig.json", "--json", OutputFileKind::kJson, {{dir / "dataset" / "rig.json", "the dataset's rig.json"}}, false},
                    "is " + (dir / "dataset" / "rig.json").string() + ", an input of this command (the dataset's rig.json)");
  ExpectFileRefused({dir / "calibration" / "none" / "rig.json", "--json", OutputFileKind::kJson, {{dir / "calibration", "ESTIMATE"}}, false},
                    "lies inside " + (dir / "calibration").string() + ", an input of this command (ESTIMATE)");
  // A new file beside the inputs is fine.
  EXPECT_NO_THROW(CheckReplaceableFile({dir / "calibration" / "scores.json", "--json", OutputFileKind::kJson, {{dir / "calibration", "ESTIMATE"}}, false}));
  EXPECT_EQ(ReadText(dir / "thesis.tex"), "\\chapter{1}");
  fs::remove_all(dir);
}

TEST(OutputFile, TwoOutputsOfOneCommandAtOnePlaceAreRefusedNamingBoth) {
  const fs::path dir = FreshDir("distinct");
  EXPECT_NO_THROW(CheckDistinctOutputs({{"--rig-out", dir / "rig.json"}, {"--frames-out", dir / "frames.json"}, {"--out", ""}}));
  try {
    CheckDistinctOutputs({{"--rig-out", dir / "x.json"}, {"--frames-out", dir / "." / "x.json"}});
    ADD_FAILURE() << "not refused";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--rig-out and --frames-out are both " + (dir / "." / "x.json").string() + ": ", 0), 0u)
        << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rigsim
