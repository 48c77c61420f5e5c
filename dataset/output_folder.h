// The folders rigsim writes its results into (render, make-rig --out, calibrate, export, demo,
// sweep), and the one rule for writing into one that exists: rigsim replaces only what it wrote.
//
// Every output folder carries a marker, `.rigsim-output`, naming what wrote it and the entries
// (files and folders) it wrote at its top level. A folder is written (or, with --force, replaced)
// only when it does not exist, is empty, or carries the marker and holds nothing else than the
// entries the marker lists and rigsim output folders of their own (calibrate's DATASET/calibration).
// Refused whatever --force says: a file, the root folder, the home folder or an ancestor of it,
// the working folder or an ancestor of it, a folder of other files or without the marker, and a
// folder that is, holds or lies inside an input of the same command. CheckOutputFolder says which,
// in the words of the command line.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace rigsim {

inline constexpr const char* kOutputMarker = ".rigsim-output";

// What a command reads, for the refusal of an output folder that would replace it.
struct CommandInput {
  std::filesystem::path path;  // a file, or a folder whose contents the command reads
  std::string what;            // how the command line names it: "--scene", "the dataset's images/"
};

struct OutputFolderRequest {
  std::filesystem::path dir;
  // How the command line names the folder, to start messages with: "--out" ("--out DIR: ...");
  // empty when the folder is a default (calibrate's DATASET/calibration): "DIR: ...".
  std::string option = "--out";
  std::string written_by = "rigsim";  // recorded in the marker: "rigsim render"
  std::vector<CommandInput> inputs;
  bool force = false;
};

struct OutputFolderState {
  enum Kind { kAbsent, kEmpty, kWrittenByRigsim } kind = kAbsent;
  std::string written_by;  // the marker's, for kWrittenByRigsim
};

// Checks that `request.dir` may be written (see the header comment); throws std::runtime_error
// saying why not and what to do. Does not look at `force`: a folder rigsim wrote is
// kWrittenByRigsim whatever it says, and the caller decides (StagedOutput replaces it only with
// force; a sweep resumes in it).
OutputFolderState CheckOutputFolder(const OutputFolderRequest& request);

// CheckOutputFolder, and a folder rigsim wrote is replaced only with `force`: what StagedOutput
// checks, for a command to check before its work.
void CheckReplaceableOutput(const OutputFolderRequest& request);

// Writes the marker into `dir`: `written_by` and the entries `dir` holds now (or `entries` when
// given: what a folder written in place, a sweep's, will hold).
void WriteOutputMarker(const std::filesystem::path& dir, const std::string& written_by,
                       std::vector<std::string> entries = {});

// Builds an output folder next to its final place and moves it there only when complete, so an
// interrupted run leaves either the previous output or nothing. The folder is checked first
// (CheckOutputFolder; one that rigsim wrote is replaced only with `force`) and gets the marker
// when committed. The destructor removes an uncommitted staging folder.
class StagedOutput {
 public:
  explicit StagedOutput(const OutputFolderRequest& request);
  StagedOutput(std::filesystem::path final_dir, bool force);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  const std::filesystem::path& staging_dir() const { return staging_; }
  // Writes the marker and replaces `final_dir` with the staging folder.
  void Commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path staging_;
  std::string written_by_;
  bool committed_ = false;
};

}  // namespace rigsim
