#include "common/data_dir.h"

#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

// An installed layout (PREFIX/bin/rigsim, PREFIX/share/rigsim), a build folder and a source tree.
struct Trees {
  TempDir root;
  fs::path prefix = root / "prefix";
  fs::path build = root / "build";
  fs::path source = root / "source";
  Trees() {
    for (const fs::path& d : {prefix / "bin", prefix / "share/rigsim/assets", build / "apps/rigsim", source / "assets"}) {
      fs::create_directories(d);
    }
  }
  DataDirSearch Search(const fs::path& program) const { return {nullptr, program, build, source}; }
};

TEST(DataDir, AnInstalledProgramReadsShareRigsimBesideIt) {
  const Trees t;
  const FoundDataDir found = FindDataDir(t.Search(t.prefix / "bin" / "rigsim"));
  EXPECT_EQ(found.dir, t.prefix / "share" / "rigsim");
  EXPECT_EQ(found.how, "beside the program " + (t.prefix / "bin" / "rigsim").string());
}

TEST(DataDir, AProgramInItsBuildFolderReadsTheSourceTree) {
  const Trees t;
  EXPECT_EQ(FindDataDir(t.Search(fs::canonical(t.build) / "apps/rigsim/rigsim")).dir, t.source);
}

TEST(DataDir, AProgramOutsideItsBuildFolderNeverReadsTheSourceTree) {
  const Trees t;
  fs::remove_all(t.prefix / "share");
  const fs::path program = t.prefix / "bin" / "rigsim";
  EXPECT_THAT([&] { FindDataDir(t.Search(program)); },
              ThrowsWith<std::runtime_error>("rigsim's data (assets/, report/web/) not found: no " +
                                                 (t.prefix / "share" / "rigsim").string() + " beside the program " +
                                                 program.string(),
                                             "cmake --install", "RIGSIM_DATA_DIR"));
}

TEST(DataDir, ABuildFolderWhoseSourceTreeIsGoneSaysSo) {
  const Trees t;
  fs::remove_all(t.source);
  EXPECT_THAT([&] { FindDataDir(t.Search(fs::canonical(t.build) / "apps/rigsim/rigsim")); },
              ThrowsWith<std::runtime_error>("the source tree of its build folder, " + t.source.string() + ", is gone",
                                             "RIGSIM_DATA_DIR"));
}

TEST(DataDir, TheVariableWinsAndIsTheOnlyPlaceLookedIn) {
  const Trees t;
  DataDirSearch search = t.Search(t.prefix / "bin" / "rigsim");
  const std::string own = (t.root / "own").string();
  search.variable = own.c_str();
  EXPECT_THAT([&] { FindDataDir(search); },
              ThrowsExactly<std::runtime_error>("RIGSIM_DATA_DIR=" + own +
                                                ": not a folder (it should hold rigsim's assets/ and report/web/)"));
  fs::create_directories(own);
  const FoundDataDir found = FindDataDir(search);
  EXPECT_EQ(found.dir, own);
  EXPECT_EQ(found.how, "from RIGSIM_DATA_DIR");
  search.variable = "";  // set but empty: as unset
  EXPECT_EQ(FindDataDir(search).dir, t.prefix / "share" / "rigsim");
}

// This test runs from the build folder: the source tree's data, found through DataPath.
TEST(DataDir, DataPathNamesTheMissingFileAndTheVariable) {
  unsetenv(kDataDirVariable);
  EXPECT_TRUE(fs::is_regular_file(DataPath("assets/scenes/street.glb")));
  EXPECT_TRUE(fs::is_regular_file(DataPath("report/web/index.html")));
  EXPECT_THAT([&] { DataPath("assets/scenes/no_such.glb"); },
              ThrowsNaming<std::runtime_error>((DataDir() / "assets/scenes/no_such.glb").string(),
                                               "missing (rigsim's data folder " + DataDir().string() +
                                                   ", the source tree of the build folder"));
  EXPECT_THAT([&] { DataPath("assets/scenes/no_such.glb"); }, ThrowsWith<std::runtime_error>("RIGSIM_DATA_DIR"));
}

}  // namespace
}  // namespace rigsim
