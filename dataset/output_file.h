// The single files rigsim writes (generate-scene --out, make-rig --rig-out and --frames-out,
// evaluate --json), under the rule of its output folders (dataset/output_folder.h) as far as a file
// allows: an existing file is replaced only with --force, and only when it is of the kind the
// command writes (a file carries no marker, so its first bytes stand for one). Refused whatever
// --force says: a folder, something else than a regular file, a file of another kind (the user's
// photo or notes), an input of the same command, an existing file inside a folder the command
// reads, and a file in a folder that does not exist. And two outputs of one command are never one
// path. Implemented beside the folders' rules
// (output_folder.cc), with the same resolution of paths.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "dataset/output_folder.h"

namespace rigsim {

enum class OutputFileKind {
  kJson,  // a JSON object: "{" after any white space
  kGlb,   // a binary glTF: "glTF"
};

struct OutputFileRequest {
  std::filesystem::path file;
  std::string option;  // how the command line names it, to start messages with: "--rig-out"
  OutputFileKind kind = OutputFileKind::kJson;
  std::vector<CommandInput> inputs;
  bool force = false;
};

// Checks that `request.file` may be written (above); throws std::runtime_error saying why not and
// what to do.
void CheckReplaceableFile(const OutputFileRequest& request);

// Two outputs of one command (option, path) must not be one file or folder, or the second would
// replace the first: throws std::runtime_error naming both options. Empty paths are skipped.
void CheckDistinctOutputs(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs);

}  // namespace rigsim
