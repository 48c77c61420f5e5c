#include "dataset/dataset.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <set>
#include <stdexcept>

#include <cerrno>
#include <csignal>

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include "geometry/json_io.h"

namespace rigsim {
namespace fs = std::filesystem;
using json_io::Get;
using json_io::Json;

FramesFile FramesFromJsonText(const std::string& text, const std::string& source) {
  const Json root = json_io::Parse(text, source);
  if (!root.is_object() || !root.contains("frames") || !root["frames"].is_array()) {
    throw std::runtime_error(source + ": expected an object with a 'frames' array");
  }
  FramesFile out;
  if (root.contains("scene")) out.scene = Get<std::string>(root, "scene", source, "root");
  if (root.contains("label_rules")) out.label_rules = Get<std::string>(root, "label_rules", source, "root");
  if (root.contains("seed")) out.seed = Get<uint64_t>(root, "seed", source, "root");
  if (root.contains("tool_version")) out.tool_version = Get<std::string>(root, "tool_version", source, "root");
  std::set<std::string> names;
  const Json& frames = root["frames"];
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::string where = "frames[" + std::to_string(i) + "]";
    Frame f;
    f.name = Get<std::string>(frames[i], "name", source, where);
    if (f.name.empty() || f.name.find('/') != std::string::npos || f.name == "." || f.name == "..") {
      throw std::runtime_error(source + ": " + where + ": frame name '" + f.name + "' is not a valid file stem");
    }
    if (!names.insert(f.name).second) {
      throw std::runtime_error(source + ": " + where + ": duplicate frame name '" + f.name + "'");
    }
    if (frames[i].contains("rig_from_world") && !frames[i]["rig_from_world"].is_null()) {
      f.rig_from_world = json_io::PoseFromJson(frames[i]["rig_from_world"], source, where + ".rig_from_world");
    }
    if (frames[i].contains("timestamp_s")) f.timestamp_s = Get<double>(frames[i], "timestamp_s", source, where);
    out.frames.push_back(std::move(f));
  }
  if (out.frames.empty()) throw std::runtime_error(source + ": 'frames' is empty");
  return out;
}

std::string FramesToJsonText(const FramesFile& frames) {
  Json list = Json::array();
  for (const Frame& f : frames.frames) {
    Json j{{"name", f.name}, {"timestamp_s", f.timestamp_s}};
    if (f.rig_from_world) j["rig_from_world"] = json_io::PoseToJson(*f.rig_from_world);
    list.push_back(std::move(j));
  }
  Json root{{"scene", frames.scene}, {"seed", frames.seed}, {"tool_version", frames.tool_version}};
  if (!frames.label_rules.empty()) root["label_rules"] = frames.label_rules;
  root["frames"] = std::move(list);
  return root.dump(2) +
         "\n";
}

FramesFile ReadFrames(const fs::path& path) { return FramesFromJsonText(json_io::ReadText(path), path.string()); }

void WriteFrames(const FramesFile& frames, const fs::path& path) {
  json_io::WriteTextAtomic(path, FramesToJsonText(frames));
}

fs::path DatasetLayout::Image(const std::string& cam, const std::string& frame) const {
  return root_ / "images" / cam / (frame + ".png");
}
fs::path DatasetLayout::Label(const std::string& cam, const std::string& frame) const {
  return root_ / "labels" / cam / (frame + ".png");
}
fs::path DatasetLayout::LabelColor(const std::string& cam, const std::string& frame) const {
  return root_ / "labels_color" / cam / (frame + ".png");
}
fs::path DatasetLayout::Instance(const std::string& cam, const std::string& frame) const {
  return root_ / "instances" / cam / (frame + ".png");
}
fs::path DatasetLayout::Depth(const std::string& cam, const std::string& frame) const {
  return root_ / "depth" / cam / (frame + ".exr");
}

fs::path DatasetLayout::DepthColor(const std::string& cam, const std::string& frame) const {
  return root_ / "depth_color" / cam / (frame + ".png");
}
fs::path DatasetLayout::InstanceColor(const std::string& cam, const std::string& frame) const {
  return root_ / "instances_color" / cam / (frame + ".png");
}
fs::path DatasetLayout::Normal(const std::string& cam, const std::string& frame) const {
  return root_ / "normals" / cam / (frame + ".exr");
}
fs::path DatasetLayout::Correspondence(const std::string& cam_a, const std::string& cam_b, const std::string& frame) const {
  return root_ / "correspondence" / cam_a / cam_b / (frame + ".exr");
}
fs::path DatasetLayout::Flow(const std::string& cam, const std::string& frame) const {
  return root_ / "flow" / cam / (frame + ".exr");
}

namespace {

// The extensions a photo in images/<cam>/ may have, in the order FindImage tries them.
const std::vector<std::string>& PhotoExtensions() {
  static const std::vector<std::string> extensions = {".png", ".jpg", ".jpeg", ".JPG", ".JPEG", ".PNG", ".tif", ".tiff", ".exr"};
  return extensions;
}

std::string PhotoExtensionList() {
  std::string list;
  for (const std::string& ext : PhotoExtensions()) list += (list.empty() ? "" : " ") + ext;
  return list;
}

}  // namespace

std::optional<fs::path> DatasetLayout::FindImage(const std::string& cam, const std::string& frame) const {
  for (const std::string& ext : PhotoExtensions()) {
    const fs::path p = root_ / "images" / cam / (frame + ext);
    if (fs::exists(p)) return p;
  }
  return std::nullopt;
}

fs::path DatasetLayout::RequireImage(const std::string& cam, const std::string& frame) const {
  if (std::optional<fs::path> found = FindImage(cam, frame)) return *found;
  throw std::runtime_error((root_ / "images" / cam / frame).string() + ".*: image missing (camera '" + cam + "', frame '" +
                           frame + "'; tried " + PhotoExtensionList() + ")");
}

std::string DatasetLayout::ImageName(const std::string& cam, const std::string& frame) const {
  const std::optional<fs::path> found = FindImage(cam, frame);
  return cam + "/" + frame + (found ? found->extension().string() : std::string(".png"));
}

FramesFile DatasetLayout::ReadFramesOrScan(const std::string& first_camera) const {
  if (fs::exists(FramesJson())) return ReadFrames(FramesJson());
  const fs::path dir = root_ / "images" / first_camera;
  if (!fs::is_directory(dir)) {
    throw std::runtime_error(dir.string() + ": no such folder (and no frames.json in " + root_.string() + ")");
  }
  std::vector<std::string> stems;
  const std::vector<std::string>& extensions = PhotoExtensions();
  for (const auto& entry : fs::directory_iterator(dir)) {
    const fs::path& p = entry.path();
    const bool photo = std::find(extensions.begin(), extensions.end(), p.extension().string()) != extensions.end();
    if (entry.is_regular_file() && photo && p.filename().string()[0] != '.') stems.push_back(p.stem().string());
  }
  std::sort(stems.begin(), stems.end());
  stems.erase(std::unique(stems.begin(), stems.end()), stems.end());
  if (stems.empty()) throw std::runtime_error(dir.string() + ": no images (" + PhotoExtensionList() + ")");
  FramesFile out;
  for (const std::string& s : stems) out.frames.push_back(Frame{s, std::nullopt, 0.0});
  return out;
}

namespace {

// Removes staging folders "<parent>/.<name>.partial-<pid>-..." left by runs that were killed
// (SIGKILL, power loss): their process is gone. Folders of live processes are left alone.
void RemoveStaleStaging(const fs::path& final_dir) {
  const fs::path parent = final_dir.parent_path().empty() ? fs::path(".") : final_dir.parent_path();
  std::string prefix = ".";  // (built with += : GCC 12 warns falsely on "." + s + "...")
  prefix += final_dir.filename().string();
  prefix += ".partial-";
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const size_t digits_end = name.find_first_not_of("0123456789", prefix.size());
    if (digits_end == prefix.size()) continue;
    const std::string pid_text = name.substr(prefix.size(), digits_end - prefix.size());
    if (pid_text.size() > 9) continue;
    const pid_t pid = pid_t(std::stol(pid_text));
    if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(it->path());
  }
  for (const fs::path& p : stale) fs::remove_all(p, ec);
}

}  // namespace

StagedOutput::StagedOutput(fs::path final_dir, bool force) : final_(std::move(final_dir)) {
  if (final_.filename().empty()) final_ = final_.parent_path();  // "out/" -> "out"
  if (fs::exists(final_) && !force) {
    throw std::runtime_error(final_.string() + ": already exists (use --force to replace it)");
  }
  RemoveStaleStaging(final_);
  static std::atomic<int> counter{0};
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
  std::string name = ".";
  for (const std::string& part : {final_.filename().string(), std::string(".partial-"), std::to_string(::getpid()),
                                  std::string("-"), std::to_string(stamp), std::string("-"),
                                  std::to_string(counter++)}) {
    name += part;
  }
  staging_ = final_.parent_path() / name;
  if (!final_.parent_path().empty()) fs::create_directories(final_.parent_path());
  fs::create_directories(staging_);
}

StagedOutput::~StagedOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedOutput::Commit() {
  if (committed_) return;
  // Swap the new output with the old one in one atomic step (renameat2 RENAME_EXCHANGE), so that
  // at every instant a complete output sits at `final_`, then drop the old one, now at staging_.
  if (fs::exists(final_)) {
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      std::error_code ec;
      fs::remove_all(staging_, ec);
      return;
    }
    // Filesystems without RENAME_EXCHANGE: move the old output aside first. An interruption
    // between the two renames leaves no output (the old one is then a stale staging folder).
    const fs::path old = staging_.string() + ".old";
    fs::rename(final_, old);
    fs::rename(staging_, final_);
    committed_ = true;
    fs::remove_all(old);
    return;
  }
  fs::rename(staging_, final_);
  committed_ = true;
}

}  // namespace rigsim
