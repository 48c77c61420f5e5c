#include "evaluation/rig_estimate.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "common/did_you_mean.h"
#include "exports/colmap.h"
#include "exports/kalibr.h"
#include "geometry/estimate_gauge.h"
#include "geometry/json_io.h"

namespace rigsim {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

std::vector<std::string> Names(const Rig& rig) {
  std::vector<std::string> names;
  for (const RigCamera& c : rig.cameras) names.push_back(c.name);
  return names;
}

// Index of camera `name` in the truth, or an error naming `source`; with `skip_unknown`, the
// number of cameras of the truth instead of the error (a camera the caller skips).
size_t CameraIndex(const Rig& truth, const std::string& name, const std::string& source, bool skip_unknown = false) {
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    if (truth.cameras[i].name == name) return i;
  }
  if (skip_unknown) return truth.cameras.size();
  std::string all;
  for (const std::string& n : Names(truth)) all += (all.empty() ? "" : ", ") + n;
  throw std::runtime_error(source + ": camera '" + name + "' is not in the dataset's rig (" + all + ")" +
                           DidYouMean(name, Names(truth)));
}

RigEstimate Empty(const std::string& method, size_t n) {
  RigEstimate e;
  e.method = method;
  e.cam_from_rig.assign(n, std::nullopt);
  e.rotation_only.assign(n, std::nullopt);
  e.open_axis.assign(n, std::nullopt);
  e.if_synchronised.assign(n, 0);
  e.rotation_std_deg.assign(n, std::nullopt);
  e.direction_std_deg.assign(n, std::nullopt);
  return e;
}

RigEstimate FromRig(const Rig& rig, const Rig& truth, const std::string& method, const std::string& source,
                    bool skip_unknown) {
  RigEstimate e = Empty(method, truth.cameras.size());
  for (const RigCamera& rc : rig.cameras) {
    const size_t c = CameraIndex(truth, rc.name, source, skip_unknown);
    if (c < truth.cameras.size()) e.cam_from_rig[c] = rc.cam_from_rig;
  }
  return e;
}

// A camera entry's 3-vector `key` of evaluation.json; throws naming the file and the camera.
Eigen::Vector3d Vector3Of(const Json& cam, const char* key, const std::string& source) {
  const Json v = cam.value(key, Json());
  if (!v.is_array() || v.size() != 3 || !std::all_of(v.begin(), v.end(), [](const Json& x) { return x.is_number(); })) {
    throw std::runtime_error(source + ": camera '" + cam.value("name", "") + "': \"" + key + "\" is not 3 numbers");
  }
  const Eigen::Vector3d out(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!out.allFinite()) {
    throw std::runtime_error(source + ": camera '" + cam.value("name", "") + "': \"" + key + "\" is not finite");
  }
  return out;
}

// A camera "placed but for one axis" (evaluation.json's open_axis and centre_across_axis), or
// nullopt for a camera without them.
std::optional<OpenAxisCentre> OpenAxisOf(const Json& cam, const std::string& source) {
  if (!cam.contains("open_axis") || cam["open_axis"].is_null()) return std::nullopt;
  OpenAxisCentre open;
  open.axis = Vector3Of(cam, "open_axis", source);
  open.centre_across_axis = Vector3Of(cam, "centre_across_axis", source);
  if (!(open.axis.norm() > 1e-12)) {
    throw std::runtime_error(source + ": camera '" + cam.value("name", "") + "': \"open_axis\" is not a direction");
  }
  open.axis.normalize();
  return open;
}

// The chordal mean of rotations (sign-invariant): the dominant eigenvector of sum q q^T.
Eigen::Quaterniond MeanRotation(const std::vector<Eigen::Quaterniond>& qs) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  for (const Eigen::Quaterniond& q : qs) m += q.coeffs() * q.coeffs().transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(m);
  Eigen::Quaterniond mean;
  mean.coeffs() = eig.eigenvectors().col(3);
  return mean.normalized();
}

std::vector<RigEstimate> FromCalibrationFolder(const fs::path& dir, const Rig& truth, bool skip_unknown) {
  const fs::path evaluation_path = dir / "evaluation.json";
  const Json evaluation = json_io::ReadFile(evaluation_path);
  if (!evaluation.contains("methods") || !evaluation["methods"].is_object()) {
    throw std::runtime_error(evaluation_path.string() + ": not a calibration's evaluation.json (no \"methods\")");
  }
  // The modes in the file's order (calibrate writes them by name; `rigsim evaluate` puts them in
  // calibrate's order).
  const nlohmann::ordered_json in_order = nlohmann::ordered_json::parse(json_io::ReadText(evaluation_path));
  std::vector<std::string> modes;
  for (const auto& [mode, unused] : in_order["methods"].items()) modes.push_back(mode);
  std::vector<RigEstimate> estimates;
  for (const std::string& mode : modes) {
    const Json& method = evaluation["methods"][mode];
    const fs::path rig_path = dir / mode / "rig.json";
    if (!fs::exists(rig_path)) throw std::runtime_error(rig_path.string() + ": missing (the calibration folder is incomplete)");
    RigEstimate e = FromRig(ReadRig(rig_path), truth, mode, rig_path.string(), skip_unknown);
    const Json rig = method.value("rig", Json::object());
    for (const Json& cam : rig.value("cameras", Json::array())) {
      if (!cam.is_object()) continue;
      const size_t c = CameraIndex(truth, cam.value("name", ""), evaluation_path.string(), skip_unknown);
      if (c >= truth.cameras.size()) continue;
      if (cam.value("holds_if_synchronised", false)) e.if_synchronised[c] = 1;
      const auto read_std = [&](const char* key, std::vector<std::optional<double>>* into) {
        if (!cam.contains(key) || !cam[key].is_number()) return;
        (*into)[c] = cam[key].get<double>();
      };
      read_std("rotation_std_deg", &e.rotation_std_deg);
      read_std("direction_std_deg", &e.direction_std_deg);
      if (cam.value("position_known", true) || !cam.contains("rotation_wxyz") || !cam["rotation_wxyz"].is_array()) {
        continue;
      }
      const Json& q = cam["rotation_wxyz"];
      e.rotation_only[c] =
          Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>()).normalized();
      e.open_axis[c] = OpenAxisOf(cam, evaluation_path.string());
    }
    e.metric = rig.value("summary", Json::object()).value("metric_scale", false);
    e.details = {{"timing", method.value("timing", Json::object())},
                 {"rig_timing", rig.value("timing", Json::object())},
                 {"pairwise", method.value("summary", Json::object())},
                 {"pairs", method.value("pairs", Json::array())}};
    estimates.push_back(std::move(e));
  }
  if (estimates.empty()) throw std::runtime_error(evaluation_path.string() + ": lists no method");
  return estimates;
}

RigEstimate FromKalibr(const fs::path& path, const Rig& truth, bool skip_unknown) {
  const std::vector<KalibrCamera> cams = ReadKalibrCamchain(path);
  RigEstimate e = Empty("kalibr", truth.cameras.size());
  // rigsim's own camchain of an estimate says its unit in a comment; Kalibr's are in metres.
  if (const std::optional<bool> metric = MetricMarkInComments(json_io::ReadText(path)); metric) {
    e.metric = *metric;
    e.notes.push_back(std::string("the camchain's comments say its lengths are ") +
                      (*metric ? "metres" : "not metres: positions are compared after fitting the scale"));
  } else {
    e.metric = true;
    e.notes.push_back("a Kalibr camchain is taken as metric: positions are compared in metres (--scale fit fits the "
                      "scale instead)");
  }
  const bool named = std::all_of(cams.begin(), cams.end(), [](const KalibrCamera& c) { return !c.name.empty(); });
  if (!named && cams.size() != truth.cameras.size()) {
    throw std::runtime_error(path.string() + ": " + std::to_string(cams.size()) + " cameras without rostopic names, " +
                             "the dataset has " + std::to_string(truth.cameras.size()) + ": cannot tell which is which");
  }
  for (size_t i = 0; i < cams.size(); ++i) {
    const size_t c = named ? CameraIndex(truth, cams[i].name, path.string() + ": " + cams[i].key, skip_unknown) : i;
    if (c >= truth.cameras.size()) continue;
    const Camera& cam = truth.cameras[c].camera;
    if (cams[i].width > 0 && (cams[i].width != cam.width() || cams[i].height != cam.height())) {
      throw std::runtime_error(path.string() + ": " + cams[i].key + " is " + std::to_string(cams[i].width) + "x" +
                               std::to_string(cams[i].height) + ", camera '" + truth.cameras[c].name + "' is " +
                               std::to_string(cam.width()) + "x" + std::to_string(cam.height()));
    }
    e.cam_from_rig[c] = cams[i].cam_from_cam0;  // the rig frame of a camchain is its cam0
  }
  return e;
}

}  // namespace

RigEstimate RigEstimateFromColmap(const std::vector<std::pair<std::string, Rigid3d>>& images, const Rig& truth,
                                  const FramesFile& frames) {
  const size_t n = truth.cameras.size();
  RigEstimate e = Empty("colmap", n);
  std::map<std::string, size_t> frame_index;
  for (size_t k = 0; k < frames.frames.size(); ++k) frame_index[frames.frames[k].name] = k;
  // [frame][camera] cam_from_world of the registered images.
  std::vector<std::vector<std::optional<Rigid3d>>> poses(frames.frames.size(), std::vector<std::optional<Rigid3d>>(n));
  int unknown = 0;
  for (const auto& [name, cam_from_world] : images) {
    const size_t slash = name.find('/');
    const std::string cam = slash == std::string::npos ? "" : name.substr(0, slash);
    const std::string frame = fs::path(name.substr(slash + 1)).stem().string();
    const auto names = Names(truth);
    const auto c = std::find(names.begin(), names.end(), cam);
    const auto k = frame_index.find(frame);
    if (c == names.end() || k == frame_index.end()) {
      ++unknown;
      continue;
    }
    poses[k->second][c - names.begin()] = cam_from_world;
  }
  if (unknown > 0) e.notes.push_back(std::to_string(unknown) + " images of the model are not <camera>/<frame> of the dataset");
  int registered = 0;
  for (size_t c = 0; c < n; ++c) {
    std::vector<Eigen::Quaterniond> rotations;
    Eigen::Vector3d translation_sum = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < poses.size(); ++k) {
      registered += poses[k][c].has_value();
      if (!poses[k][c] || !poses[k][0]) continue;
      const Rigid3d cam_from_cam0 = *poses[k][c] * poses[k][0]->Inverse();
      rotations.push_back(cam_from_cam0.rotation);
      translation_sum += cam_from_cam0.translation;
    }
    if (rotations.empty()) continue;
    e.cam_from_rig[c] = Rigid3d(MeanRotation(rotations), translation_sum / static_cast<double>(rotations.size()));
  }
  const int total = static_cast<int>(n * poses.size());
  if (registered < total) {
    e.notes.push_back("COLMAP registered " + std::to_string(registered) + " of " + std::to_string(total) + " images");
  }
  return e;
}

EstimateCameras ReadEstimateCameras(const fs::path& estimate) {
  EstimateCameras out;
  const std::string ext = estimate.extension().string();
  if (!fs::exists(estimate)) throw std::runtime_error(estimate.string() + ": no such file or folder");
  const auto names_of = [&](const Rig& rig) {
    for (const RigCamera& c : rig.cameras) out.names.push_back(c.name);
  };
  if (fs::is_directory(estimate) && fs::exists(estimate / "evaluation.json")) {
    const fs::path evaluation_path = estimate / "evaluation.json";
    const nlohmann::ordered_json evaluation = nlohmann::ordered_json::parse(json_io::ReadText(evaluation_path), nullptr, false);
    if (evaluation.is_discarded() || !evaluation.contains("methods") || !evaluation["methods"].is_object() ||
        evaluation["methods"].empty()) {
      throw std::runtime_error(evaluation_path.string() + ": not a calibration's evaluation.json (no \"methods\")");
    }
    const fs::path rig_path = estimate / evaluation["methods"].begin().key() / "rig.json";
    if (!fs::exists(rig_path)) throw std::runtime_error(rig_path.string() + ": missing (the calibration folder is incomplete)");
    names_of(ReadRig(rig_path));
  } else if (fs::is_regular_file(estimate) && ext == ".json") {
    names_of(RigFromJsonText(json_io::ReadText(estimate), estimate.string()));
  } else if (fs::is_regular_file(estimate) && (ext == ".yaml" || ext == ".yml")) {
    for (const KalibrCamera& c : ReadKalibrCamchain(estimate)) {
      out.named = out.named && !c.name.empty();
      out.names.push_back(c.name.empty() ? c.key : c.name);
    }
  } else if (fs::is_directory(estimate) || estimate.filename() == "images.txt") {
    out.ordered = false;
    std::set<std::string> frames;
    for (const ColmapImage& image : ReadColmapImages(FindColmapTextModel(estimate) / "images.txt")) {
      const size_t slash = image.name.find('/');
      if (slash == std::string::npos) continue;
      const std::string cam = image.name.substr(0, slash);
      if (std::find(out.names.begin(), out.names.end(), cam) == out.names.end()) out.names.push_back(cam);
      frames.insert(fs::path(image.name.substr(slash + 1)).stem().string());
    }
    for (const std::string& f : frames) out.colmap_frames.frames.push_back({f, std::nullopt, 0.0});
  } else {
    throw std::runtime_error(estimate.string() +
                             ": not an estimate rigsim reads (a rig.json, a calibration folder, a COLMAP text model "
                             "folder or a Kalibr camchain.yaml)");
  }
  return out;
}

std::vector<RigEstimate> ReadRigEstimates(const fs::path& estimate, const Rig& truth, const FramesFile& frames,
                                          EstimateScale scale, bool skip_unknown_cameras) {
  std::vector<RigEstimate> estimates;
  const std::string ext = estimate.extension().string();
  if (!fs::exists(estimate)) throw std::runtime_error(estimate.string() + ": no such file or folder");
  if (fs::is_directory(estimate) && fs::exists(estimate / "evaluation.json")) {
    estimates = FromCalibrationFolder(estimate, truth, skip_unknown_cameras);
  } else if (fs::is_regular_file(estimate) && ext == ".json") {
    const std::string text = json_io::ReadText(estimate);
    estimates.push_back(
        FromRig(RigFromJsonText(text, estimate.string()), truth, "rig.json", estimate.string(), skip_unknown_cameras));
    // An estimate's rig.json says its unit; any other is taken as unit scale.
    if (const auto gauge = EstimateGaugeFromJsonText(text, estimate.string())) estimates.back().metric = gauge->metric;
  } else if (fs::is_regular_file(estimate) && (ext == ".yaml" || ext == ".yml")) {
    estimates.push_back(FromKalibr(estimate, truth, skip_unknown_cameras));
  } else if (fs::is_directory(estimate) || estimate.filename() == "images.txt") {
    const fs::path model = FindColmapTextModel(estimate);
    std::vector<std::pair<std::string, Rigid3d>> images;
    for (const ColmapImage& image : ReadColmapImages(model / "images.txt")) images.push_back({image.name, image.cam_from_world});
    estimates.push_back(RigEstimateFromColmap(images, truth, frames));
    if (model != estimate) estimates.back().notes.push_back("read the model in " + model.string());
  } else {
    throw std::runtime_error(estimate.string() +
                             ": not an estimate rigsim reads (a rig.json, a calibration folder, a COLMAP text model "
                             "folder or a Kalibr camchain.yaml)");
  }
  for (RigEstimate& e : estimates) {
    if (scale == EstimateScale::kMetric) e.metric = true;
    if (scale == EstimateScale::kFit) e.metric = false;
  }
  return estimates;
}

}  // namespace rigsim
