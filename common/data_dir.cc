#include "common/data_dir.h"

#include <cstdlib>
#include <stdexcept>
#include <system_error>

namespace rigsim {
namespace fs = std::filesystem;

namespace {

const char* const kWhatToDo = "set RIGSIM_DATA_DIR to a folder that holds assets/ and report/web/";

bool IsInside(const fs::path& path, const fs::path& folder) {
  if (path.empty() || folder.empty()) return false;
  std::error_code ec;
  const fs::path canonical_folder = fs::weakly_canonical(folder, ec);
  if (ec) return false;
  const fs::path relative = path.lexically_relative(canonical_folder);
  return !relative.empty() && *relative.begin() != "..";
}

}  // namespace

FoundDataDir FindDataDir(const DataDirSearch& search) {
  if (search.variable != nullptr && *search.variable != '\0') {
    const fs::path dir = search.variable;
    if (!fs::is_directory(dir)) {
      throw std::runtime_error(std::string(kDataDirVariable) + "=" + dir.string() +
                               ": not a folder (it should hold rigsim's assets/ and report/web/)");
    }
    return {dir, std::string("from ") + kDataDirVariable};
  }
  const fs::path installed = (search.program.parent_path() / ".." / "share" / "rigsim").lexically_normal();
  if (!search.program.empty() && fs::is_directory(installed)) {
    return {installed, "beside the program " + search.program.string()};
  }
  std::string looked = "no " + installed.string() + " beside the program " + search.program.string();
  if (IsInside(search.program, search.build_tree)) {
    if (fs::is_directory(search.source_tree)) {
      return {search.source_tree, "the source tree of the build folder " + search.build_tree.string()};
    }
    looked += ", and the source tree of its build folder, " + search.source_tree.string() + ", is gone";
  }
  throw std::runtime_error("rigsim's data (assets/, report/web/) not found: " + looked +
                           "; install rigsim with `cmake --install BUILD_DIR --prefix PREFIX`, or " + kWhatToDo);
}

DataDirSearch ThisProgramsDataDirSearch() {
  DataDirSearch search;
  search.variable = std::getenv(kDataDirVariable);
  std::error_code ec;
  search.program = fs::read_symlink("/proc/self/exe", ec);
  search.build_tree = RIGSIM_BUILD_TREE;
  search.source_tree = RIGSIM_SOURCE_TREE;
  return search;
}

fs::path DataDir() { return FindDataDir(ThisProgramsDataDirSearch()).dir; }

fs::path DataPath(const fs::path& relative) {
  const FoundDataDir found = FindDataDir(ThisProgramsDataDirSearch());
  const fs::path path = found.dir / relative;
  if (!fs::exists(path)) {
    throw std::runtime_error(path.string() + ": missing (rigsim's data folder " + found.dir.string() + ", " + found.how +
                             "; " + kWhatToDo + ")");
  }
  return path;
}

}  // namespace rigsim
