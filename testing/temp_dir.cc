#include "testing/temp_dir.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <mutex>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "testing/test_name.h"

namespace rigsim {
namespace {

// The folders of the TempDirs alive in this process: a second one in the same test gets a suffix.
std::mutex live_mutex;
std::set<std::filesystem::path> live;

bool RunningTestFailed(bool suite_level) {
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  if (!suite_level) return ::testing::Test::HasFailure();
  const ::testing::TestSuite* suite = unit.current_test_suite();
  return suite == nullptr || suite->Failed() || suite->ad_hoc_test_result().Failed();
}

}  // namespace

TempDir::TempDir() {
  RunningTest test = CurrentTest();
  suite_level_ = test.whole_suite;
  std::replace(test.name.begin(), test.name.end(), '/', '_');  // parameterised tests' names
  const std::string base =
      (std::filesystem::temp_directory_path() / ("rigsim_" + test.name + "_" + std::to_string(::getpid()))).string();
  {
    std::lock_guard<std::mutex> lock(live_mutex);
    path_ = base;
    for (int n = 2; live.count(path_); ++n) path_ = base + "_" + std::to_string(n);
    live.insert(path_);
  }
  std::filesystem::remove_all(path_);  // left by an earlier process of the same id
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  {
    std::lock_guard<std::mutex> lock(live_mutex);
    live.erase(path_);
  }
  if (RunningTestFailed(suite_level_)) {
    std::fprintf(stderr, "TempDir: the test failed; its folder is kept for debugging: %s\n", path_.c_str());
    return;
  }
  std::error_code ignored;  // a destructor must not throw; a folder left behind is harmless
  std::filesystem::remove_all(path_, ignored);
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::map<std::string, std::string> FilesUnder(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[std::filesystem::relative(e.path(), dir).string()] = ReadFile(e.path());
  }
  return files;
}

void WriteFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace rigsim
