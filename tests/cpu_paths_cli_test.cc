// One binary on every node of a cluster: the calibrator's CPU paths (calibrator/features/cpu_path.h) give
// the same calibration bytes, and so does OpenCV whatever its own dispatch would choose, as rigsim
// holds it to its baseline; so a sweep split over machines with and without AVX2 or AVX-512 merges
// into what one machine writes. RIGSIM_CPU_PATH forces each path this CPU has; OPENCV_CPU_DISABLE
// (OpenCV's own variable) turns its dispatched paths off as on a CPU with SSE2 only. (Embree runs
// its SSE2 kernels on every CPU: renderer/embree_scene_test.cc.)
#include <cstdlib>
#include <filesystem>
#include <map>
#include <utility>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "calibrator/features/cpu_path.h"
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

// Sets an environment variable for the commands the test runs from here on, and unsets it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::string_view value) : name_(name) { setenv(name, std::string(value).c_str(), 1); }
  ~ScopedEnv() { unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

// OpenCV's dispatched paths in Debian's build (its baseline is SSE2): turned off, OpenCV runs as
// on a CPU without them.
constexpr const char* kOpenCvDispatchedFeatures = "SSE3,SSSE3,SSE4_1,POPCNT,SSE4_2,FP16,AVX,FMA3,AVX2,AVX512_SKX";

// Expects the files `name` wrote to be those `first` wrote (and no other).
void ExpectSameFiles(const std::map<std::string, std::string>& first, const std::map<std::string, std::string>& files,
                     const std::string& name) {
  ASSERT_FALSE(files.empty()) << name;
  EXPECT_EQ(files.size(), first.size()) << name;
  for (const auto& [file, text] : first) {
    ASSERT_TRUE(files.count(file)) << name << " did not write " << file;
    EXPECT_TRUE(files.at(file) == text) << name << " wrote another " << file << " than the first run";
  }
}

class CpuPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(RunRigsim({"make-rig", "ring", "--cameras", "4", "--frames", "2", "--width", "480", "--height", "270",
                         "--out", (dir_ / "rig").string()},
                        dir_ / "make-rig")
                  .code,
              0);
  }

  // Renders the street through the rig into `name`; the files it wrote.
  std::map<std::string, std::string> Render(const std::string& name) {
    const std::string scene = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";
    const CliResult run = RunRigsim({"render", "--scene", scene, "--rig", (dir_ / "rig" / "rig.json").string(),
                                     "--frames", (dir_ / "rig" / "frames.json").string(), "--out",
                                     (dir_ / name).string(), "--spp", "1"},
                                    dir_ / ("render-" + name));
    EXPECT_EQ(run.code, 0) << name << ": " << run.err;
    return Contents(dir_ / name);
  }

  // Calibrates the dataset `data` into `name`; the files it wrote.
  std::map<std::string, std::string> Calibrate(const std::string& data, const std::string& name) {
    const fs::path out = dir_ / name;
    const CliResult run = RunRigsim({"calibrate", (dir_ / data).string(), "--semantics", "none,gated", "--out",
                                     out.string()},
                                    dir_ / ("calibrate-" + name));
    EXPECT_TRUE(run.code == 0 || run.code == 3) << name << ": " << run.err;  // 3: a camera without a full pose
    return Contents(out);
  }

  const TempDir dir_;
};

TEST_F(CpuPaths, EveryPathTheCpuHasWritesTheSameCalibration) {
  Render("data");
  const std::map<std::string, std::string> first = Calibrate("data", "calibration");
  for (CpuPath path : SupportedCpuPaths()) {
    const std::string name(CpuPathName(path));
    const ScopedEnv forced("RIGSIM_CPU_PATH", name);
    ExpectSameFiles(first, Calibrate("data", "calibration-" + name), name);
  }
  // A node with SSE2 only, as near as one machine can act it: the baseline path, with OpenCV's
  // dispatch turned off from outside (which changes nothing, as rigsim holds OpenCV to its
  // baseline) and glibc's libm taking its functions without FMA (whose last bits differ).
  const ScopedEnv baseline("RIGSIM_CPU_PATH", CpuPathName(CpuPath::kBaseline));
  const ScopedEnv opencv_baseline("OPENCV_CPU_DISABLE", kOpenCvDispatchedFeatures);
  const ScopedEnv libm_baseline("GLIBC_TUNABLES", "glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4");
  ExpectSameFiles(first, Calibrate("data", "calibration-sse2-only"), "baseline with OPENCV_CPU_DISABLE");
}

TEST_F(CpuPaths, APathTheCpuLacksOrAWrongNameStopsTheCommandBeforeItWrites) {
  const std::pair<const char*, std::string> cases[] = {
      {"RIGSIM_CPU_PATH", "avx3"}, {"RIGSIM_CPU_PATH", "avx512-vnni"}};
  for (const auto& [variable, value] : cases) {
    if (value == "avx512-vnni" && CpuSupports(CpuPath::kAvx512Vnni)) continue;  // this CPU has it
    const ScopedEnv forced(variable, value);
    const fs::path out = dir_ / ("rig-" + value);
    const CliResult run = RunRigsim({"make-rig", "ring", "--out", out.string()}, dir_ / value);
    EXPECT_EQ(run.code, 1) << variable << "=" << value;
    EXPECT_FALSE(fs::exists(out)) << value;
    EXPECT_TRUE(StagingFolders(out).empty()) << value;
  }
}

}  // namespace
}  // namespace rigsim
