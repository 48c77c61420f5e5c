// A fresh temporary folder per test, and reading and writing the files a test puts there.
//
//   TEST(Suite, Name) {
//     const TempDir dir;                      // <tmp>/rigsim_Suite.Name_<pid>, empty
//     WriteFile(dir / "rig.json", text);
//     EXPECT_EQ(ReadFile(dir / "rig.json"), text);
//   }                                         // removed here, unless the test failed
//
// The folder is named after the running test and the process id, so that parallel ctest runs
// (one process per test) never share one. A second TempDir alive in the same test gets "_2", "_3".
// Made in SetUpTestSuite, it is named after the suite (rigsim_Suite_<pid>) and belongs to every test
// of it. When its test (or any test of its suite) has failed, the folder is kept for debugging and
// its path printed; otherwise it is removed with the object.
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace rigsim {

class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  operator const std::filesystem::path&() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& relative) const { return path_ / relative; }
  std::string string() const { return path_.string(); }

 private:
  std::filesystem::path path_;
  bool suite_level_ = false;
};

// The file's bytes; "" when it cannot be read (a test then compares and fails on what it expected).
std::string ReadFile(const std::filesystem::path& path);
// Writes `bytes` (text or binary) to `path`, replacing it; throws std::runtime_error when it cannot.
void WriteFile(const std::filesystem::path& path, const std::string& bytes);
// Every regular file below `dir` by its path relative to `dir`, with its bytes: for comparing two
// output folders byte for byte.
std::map<std::string, std::string> FilesUnder(const std::filesystem::path& dir);

}  // namespace rigsim
