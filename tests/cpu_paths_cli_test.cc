// One binary on every node of a cluster: the calibrator's CPU paths (calibrator/cpu_path.h) give
// the same calibration bytes, so a sweep split over machines with and without AVX2 or AVX-512
// merges into what one machine writes. RIGSIM_CPU_PATH forces each path this CPU has.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "calibrator/cpu_path.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

// Drops the timings ("..._time_s", "seconds"), which differ from run to run by nature.
void DropTimings(nlohmann::json* j) {
  if (j->is_object()) {
    for (auto it = j->begin(); it != j->end();) {
      const std::string& key = it.key();
      const bool timing = key == "seconds" || (key.size() >= 6 && key.compare(key.size() - 6, 6, "time_s") == 0);
      if (timing) {
        it = j->erase(it);
      } else {
        DropTimings(&it.value());
        ++it;
      }
    }
  } else if (j->is_array()) {
    for (nlohmann::json& v : *j) DropTimings(&v);
  }
}

// Every file under `root` by its path relative to it: JSON without timings, other files as bytes.
std::map<std::string, std::string> Contents(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    std::string text = ReadFile(entry.path());
    if (entry.path().extension() == ".json") {
      nlohmann::json j = nlohmann::json::parse(text);
      DropTimings(&j);
      text = j.dump();
    }
    files[fs::relative(entry.path(), root).string()] = text;
  }
  return files;
}

class ForcedCpuPath {
 public:
  explicit ForcedCpuPath(std::string_view name) { setenv("RIGSIM_CPU_PATH", std::string(name).c_str(), 1); }
  ~ForcedCpuPath() { unsetenv("RIGSIM_CPU_PATH"); }
};

TEST(CpuPaths, EveryPathTheCpuHasWritesTheSameCalibration) {
  const TempDir dir;
  const std::string scene = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";
  ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "4", "--frames", "2", "--width", "480", "--height", "270",
                       "--out", (dir / "rig").string()},
                      dir / "make-rig")
                .code,
            0);
  const CliResult render = RunRigsim({"render", "--scene", scene, "--rig", (dir / "rig" / "rig.json").string(),
                                      "--frames", (dir / "rig" / "frames.json").string(), "--out",
                                      (dir / "data").string(), "--spp", "1"},
                                     dir / "render");
  ASSERT_EQ(render.code, 0) << render.err;
  std::map<std::string, std::string> first;
  for (CpuPath path : SupportedCpuPaths()) {
    const std::string name(CpuPathName(path));
    const ForcedCpuPath forced(name);
    const fs::path out = dir / ("calibration-" + name);
    const CliResult run = RunRigsim({"calibrate", (dir / "data").string(), "--semantics", "none,gated", "--out",
                                     out.string()},
                                    dir / ("calibrate-" + name));
    ASSERT_TRUE(run.code == 0 || run.code == 3) << name << ": " << run.err;  // 3: a camera without a full pose
    const std::map<std::string, std::string> files = Contents(out);
    ASSERT_FALSE(files.empty()) << name;
    if (first.empty()) {
      first = files;
      continue;
    }
    ASSERT_EQ(files.size(), first.size()) << name;
    for (const auto& [file, text] : first) {
      ASSERT_TRUE(files.count(file)) << name << " did not write " << file;
      EXPECT_TRUE(files.at(file) == text) << name << " wrote another " << file << " than the baseline path";
    }
  }
  if (SupportedCpuPaths().size() < 2) GTEST_SKIP() << "this CPU has the baseline path only: nothing to compare";
}

TEST(CpuPaths, APathTheCpuLacksOrAWrongNameStopsTheCommandBeforeItWrites) {
  const TempDir dir;
  for (const std::string value : {"avx3", "avx512-vnni"}) {
    if (value == "avx512-vnni" && CpuSupports(CpuPath::kAvx512Vnni)) continue;  // this CPU has it
    const ForcedCpuPath forced(value);
    const fs::path out = dir / ("rig-" + value);
    const CliResult run = RunRigsim({"make-rig", "ring", "--out", out.string()}, dir / value);
    EXPECT_EQ(run.code, 1) << value;
    EXPECT_FALSE(fs::exists(out)) << value;
    EXPECT_TRUE(StagingFolders(out).empty()) << value;
  }
}

}  // namespace
}  // namespace rigsim
