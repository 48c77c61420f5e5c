// Fuzzes the readers of other tools' rig files (rigs/rig_import.h: Kalibr camchain, COLMAP rigs.txt
// and rig_config.json with their model, DGP calibration with its scene, nuScenes calibrated_sensor
// with its tables), then requires that an accepted rig has a pose for every camera and survives
// rig.json.
//
// Input: one byte choosing the format, then the format's files separated by NUL bytes (the file
// given to make-rig first, the files it reads beside it after), written to a private folder that
// holds nothing else.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigs/rig_import.h"

namespace {

namespace fs = std::filesystem;

// Leaked on purpose: the exit handler that removes the folder runs after static destructors.
const fs::path& Folder() {
  static const fs::path* dir = [] {
    const auto d = fs::temp_directory_path() / ("rigsim_fuzz_rig_import_" + std::to_string(::getpid()));
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(Folder(), ec);
    });
    return new fs::path(d);
  }();
  return *dir;
}

// Per format, the files in the order the input gives them; the first is the one read.
const std::vector<std::vector<std::string>> kFormats = {
    {"camchain.yaml"},
    {"rigs.txt", "cameras.txt", "images.txt"},
    {"rig_config.json", "cameras.txt", "images.txt"},
    {"scene/calibration/c.json", "scene/scene_s.json"},
    {"calibrated_sensor.json", "sensor.json", "sample_data.json"},
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::vector<std::string>& files = kFormats[data[0] % kFormats.size()];
  std::error_code ec;
  fs::remove_all(Folder(), ec);
  fs::create_directories(Folder() / "scene" / "calibration");
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  size_t begin = 0;
  for (size_t k = 0; k < files.size() && begin <= rest.size(); ++k) {
    const size_t end = std::min(rest.find('\0', begin), rest.size());
    std::ofstream out(Folder() / files[k], std::ios::binary | std::ios::trunc);
    out.write(rest.data() + begin, std::streamsize(end - begin));
    begin = end + 1;
  }
  rigsim::Rig rig;
  try {
    rig = rigsim::ImportRig(Folder() / files[0]);
  } catch (const std::runtime_error&) {
    return 0;  // rejected with a message: fine
  }
  const bool is_rig_json = rigsim::DetectRigFileFormat(Folder() / files[0]) == rigsim::RigFileFormat::kRigJson;
  const rigsim::Rig back = rigsim::RigFromJsonText(rigsim::RigToJsonText(rig), "round trip");
  if (back.cameras.size() != rig.cameras.size()) __builtin_trap();
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    if (!is_rig_json && !rig.cameras[i].cam_from_rig) __builtin_trap();  // every import places every camera
    if (back.cameras[i].camera.params() != rig.cameras[i].camera.params()) __builtin_trap();
  }
  return 0;
}
