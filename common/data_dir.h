// Where rigsim's shipped data are: assets/ (the scenes, example rigs, label rules) and report/web/
// (the teaching report's page). The data folder holds them under those names, so a path into it
// reads the same in the source tree and in an installed copy ("assets/scenes/street.glb").
// Looked for, in order:
//   1. $RIGSIM_DATA_DIR, when set (and then nowhere else);
//   2. ../share/rigsim beside the running program (/proc/self/exe), as `cmake --install` lays it out;
//   3. the source tree, for a program that runs from the build folder it was built in (the tests,
//      the benchmarks, scripts/); an installed or copied program never reads the source tree.
#pragma once

#include <filesystem>
#include <string>

namespace rigsim {

inline constexpr const char* kDataDirVariable = "RIGSIM_DATA_DIR";

// The data folder. Throws std::runtime_error saying where it looked and naming RIGSIM_DATA_DIR
// when there is none.
std::filesystem::path DataDir();

// `relative` inside the data folder ("report/web/index.html"). Throws std::runtime_error naming
// the missing file, where the data folder was found and RIGSIM_DATA_DIR when it is not there.
std::filesystem::path DataPath(const std::filesystem::path& relative);

// What the lookup goes by, apart so that tests can give their own.
struct DataDirSearch {
  const char* variable = nullptr;        // RIGSIM_DATA_DIR's value; null when unset
  std::filesystem::path program;         // the running program's path
  std::filesystem::path build_tree;      // the folder the program was built in
  std::filesystem::path source_tree;     // the sources it was built from
};

struct FoundDataDir {
  std::filesystem::path dir;
  std::string how;  // in words: "RIGSIM_DATA_DIR", "beside the program /p/bin/rigsim", ...
};

// The lookup itself (DataDir() gives it the real values). Throws as DataDir().
FoundDataDir FindDataDir(const DataDirSearch& search);

// DataDirSearch of this process: its environment, /proc/self/exe and the trees it was built with.
DataDirSearch ThisProgramsDataDirSearch();

}  // namespace rigsim
