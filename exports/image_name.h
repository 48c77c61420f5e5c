// How exports name a dataset's images: camera `cam`'s image of frame `frame`, relative to the
// images folder (COLMAP's per-camera image prefix).
#pragma once

#include <functional>
#include <string>

namespace rigsim {

using ImageNameFn = std::function<std::string(const std::string& cam, const std::string& frame)>;

// "<cam>/<frame>.png": what render writes.
inline std::string DefaultImageName(const std::string& cam, const std::string& frame) { return cam + "/" + frame + ".png"; }

}  // namespace rigsim
