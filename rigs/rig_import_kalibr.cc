// Kalibr camchain.yaml -> rig: the reader of exports/kalibr.h, the rig frame cam0's.
#include <set>
#include <stdexcept>

#include "exports/kalibr.h"
#include "rigs/rig_import.h"

namespace rigsim {

Rig RigFromKalibrCamchain(const std::filesystem::path& path) {
  const std::vector<KalibrCamera> cameras = ReadKalibrCamchain(path);
  // Cameras are named by their rostopic (/<name>/image_raw, as the export writes it) when that
  // names each one apart, else by their keys (cam0, cam1, ...).
  std::set<std::string> names;
  for (const KalibrCamera& c : cameras) {
    if (!c.name.empty()) names.insert(c.name);
  }
  const bool by_topic = names.size() == cameras.size();
  Rig rig;
  for (const KalibrCamera& c : cameras) {
    RigCamera rc;
    rc.name = by_topic ? c.name : c.key;
    try {
      rc.camera = KalibrIntrinsics(c);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(path.string() + ": " + c.key + ": " + e.what());
    }
    rc.cam_from_rig = c.cam_from_cam0;
    rig.cameras.push_back(std::move(rc));
  }
  return rig;
}

}  // namespace rigsim
