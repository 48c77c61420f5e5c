#include "pipeline/rig_masks.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <stdexcept>

#include "common/did_you_mean.h"
#include "common/param_spec.h"
#include "dataset/image_io.h"

namespace rigsim {
namespace fs = std::filesystem;
namespace {

std::string LowerCase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The file's pixels as a keep mask: 255 where a grey or colour value is not 0, else 0.
ImageU8 KeepMaskOfFile(const fs::path& file) {
  const ImageU8 image = ReadImageU8(file);
  // Grey+alpha: grey only; RGB(A): R, G and B.
  const int colours = image.channels >= 3 ? 3 : 1;
  ImageU8 keep(image.width, image.height, 1, 0);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      bool any = false;
      for (int c = 0; c < colours; ++c) any = any || image.at(x, y, c) != 0;
      keep.at(x, y) = any ? 255 : 0;
    }
  }
  return keep;
}

}  // namespace

const CameraMask* RigMasks::Of(const std::string& name) const {
  for (const CameraMask& m : masks) {
    if (m.camera == name) return &m;
  }
  return nullptr;
}

RigMasks ReadRigMasks(const fs::path& dir, const Rig& rig, const fs::path& rig_json,
                      const std::function<void(const std::string&)>& warn) {
  const std::string where = "--mask " + dir.string();
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw std::runtime_error(where + ": no such folder");
  if (!fs::is_directory(dir, ec)) {
    throw std::runtime_error(where + ": not a folder (give a folder holding one <camera>.png per camera)");
  }
  std::vector<std::string> names;
  for (const RigCamera& rc : rig.cameras) names.push_back(rc.name);

  // Every file of the folder, sorted, so that the first problem named is the same on every machine.
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<fs::path> mask_of(rig.cameras.size());  // per camera, its PNG or empty
  for (const fs::path& f : files) {
    const std::string stem = f.stem().string();
    const int cam = rig.FindCamera(stem);
    if (cam >= 0 && LowerCase(f.extension().string()) == ".png") mask_of[cam] = f;
  }
  for (const fs::path& f : files) {
    const std::string stem = f.stem().string();
    const bool png = LowerCase(f.extension().string()) == ".png";
    const int cam = rig.FindCamera(stem);
    const bool names_camera = cam >= 0;
    if (png && !names_camera) {
      throw std::runtime_error(f.string() + ": no camera '" + stem + "' in " + rig_json.string() +
                               DidYouMean(stem, names) + "; its cameras are " + JoinNames(names) +
                               " (a mask is <camera>.png)");
    }
    // CAM.jpg alone is a mask in the wrong format; beside CAM.png (a drawing's source) it is not read.
    if (!png && names_camera && mask_of[cam].empty()) {
      throw std::runtime_error(f.string() + ": masks are PNG files (lossless, black = no features): write " +
                               (dir / (stem + ".png")).string());
    }
  }

  RigMasks out;
  out.folder = dir;
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const RigCamera& rc = rig.cameras[c];
    const fs::path& file = mask_of[c];
    if (file.empty()) {
      out.cameras_without.push_back(rc.name);
      continue;
    }
    CameraMask m;
    m.camera = rc.name;
    m.file = file;
    m.keep = KeepMaskOfFile(file);
    const int w = rc.camera.width(), h = rc.camera.height();
    if (!m.keep.SameSize(w, h)) {
      throw std::runtime_error(file.string() + ": the mask is " + std::to_string(m.keep.width) + "x" +
                               std::to_string(m.keep.height) + " but camera " + rc.name + "'s images are " +
                               std::to_string(w) + "x" + std::to_string(h) + " (" + rig_json.string() +
                               "); a mask has its camera's image size");
    }
    const size_t hidden = static_cast<size_t>(std::count(m.keep.data.begin(), m.keep.data.end(), uint8_t{0}));
    if (hidden == m.keep.data.size()) {
      throw std::runtime_error(file.string() + ": the mask is black everywhere, which leaves camera " + rc.name +
                               " no features (black = no features, anything else = features)");
    }
    m.hidden_fraction = m.keep.data.empty() ? 0.0 : double(hidden) / double(m.keep.data.size());
    out.masks.push_back(std::move(m));
  }
  if (out.masks.empty()) {
    throw std::runtime_error(where + ": no mask for any camera of " + rig_json.string() + "; name them <camera>.png: " +
                             JoinNames(names));
  }
  if (!out.cameras_without.empty()) {
    warn(where + " has no mask for " + JoinNames(out.cameras_without) + ": " +
         (out.cameras_without.size() == 1 ? "its" : "their") + " features are not masked");
  }
  return out;
}

std::string DescribeRigMasks(const RigMasks& masks, size_t num_cameras) {
  std::string out = masks.folder.string() + " (";
  if (masks.cameras_without.empty()) {
    out += std::to_string(masks.masks.size()) + (masks.masks.size() == 1 ? " camera" : " cameras");
  } else {
    out += std::to_string(masks.masks.size()) + " of " + std::to_string(num_cameras) + " cameras; " +
           JoinNames(masks.cameras_without) + (masks.cameras_without.size() == 1 ? " has" : " have") + " none";
  }
  return out + ")";
}

}  // namespace rigsim
