// The camera pairs of a report: each pair's matches per frame and mode with their flags, the
// ground-truth overlap, the relative poses; and the self-test's reference values.
#include <cmath>
#include <filesystem>
#include <optional>

#include "dataset/capture_poses.h"
#include "dataset/ground_truth.h"
#include "dataset/image_io.h"
#include "geometry/json_io.h"
#include "report/report_images.h"
#include "report/report_parts.h"

namespace rigsim::report_parts {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// Match flags of the pair data: bit 0 inlier of the two-view estimate, bit 1 checked against the
// ground truth, bit 2 correct by it.
constexpr uint8_t kInlier = 1, kChecked = 2, kCorrect = 4;

// The true range images of one frame, per camera (empty where absent).
std::vector<ImageF> FrameRanges(const ReportContext& ctx, int f) {
  const DatasetLayout layout = ctx.Layout();
  std::vector<ImageF> ranges(ctx.NumCameras());
  for (int c = 0; c < ctx.NumCameras(); ++c) {
    const fs::path path = layout.Depth(ctx.run.inputs.rig.cameras[c].name, ctx.run.inputs.frames.frames[f].name);
    if (fs::exists(path)) ranges[c] = ReadImageF(path);
  }
  return ranges;
}

// 1 per grid cell of A whose centre pixel's surface B sees (depth-tested, each view at its capture
// time), row-major.
std::vector<uint8_t> OverlapGrid(const Camera& cam_a, const ImageF& range_a, const ViewPose& pose_a, const Camera& cam_b,
                                 const ImageF& range_b, const ViewPose& pose_b, int gw, int gh) {
  std::vector<uint8_t> grid(size_t(gw) * gh, 0);
  for (int y = 0; y < gh; ++y) {
    for (int x = 0; x < gw; ++x) {
      const Eigen::Vector2d px((x + 0.5) * cam_a.width() / gw - 0.5, (y + 0.5) * cam_a.height() / gh - 0.5);
      grid[size_t(y) * gw + x] = TransferPixel(px, cam_a, range_a, pose_a, cam_b, range_b, pose_b).has_value();
    }
  }
  return grid;
}

Json Curve(const std::vector<std::optional<Eigen::Vector2d>>& curve) {
  Json j = Json::array();
  for (const auto& p : curve) j.push_back(p ? Json({p->x(), p->y()}) : Json(nullptr));
  return j;
}

// A pixel of A whose range is smooth around it (the page lifts it from a coarser range grid):
// within 1% over 7x7 pixels.
bool SmoothRange(const ImageF& range, const Eigen::Vector2d& px) {
  const int cx = int(std::lround(px.x())), cy = int(std::lround(px.y()));
  if (cx < 3 || cy < 3 || cx + 3 >= range.width || cy + 3 >= range.height) return false;
  float lo = range.at(cx, cy), hi = lo;
  for (int dy = -3; dy <= 3; ++dy) {
    for (int dx = -3; dx <= 3; ++dx) {
      lo = std::min(lo, range.at(cx + dx, cy + dy));
      hi = std::max(hi, range.at(cx + dx, cy + dy));
    }
  }
  return lo > 0 && hi < lo * 1.01f;
}

// The self-test's reference values (report_writer.h): a correct inlier of pair p on a smooth
// surface (else any inlier), its epipolar curves under the truth and the first mode's estimate,
// its true correspondence from the full-size depth; null when the pair has no inlier.
Json SelfTestReference(const ReportContext& ctx, size_t p, int f, int a, int b, const Rigid3d& true_b_from_a,
                       const std::vector<ImageF>& ranges) {
  const Rig& rig = ctx.run.inputs.rig;
  const Camera& cam_a = rig.cameras[a].camera;
  const Camera& cam_b = rig.cameras[b].camera;
  const PairwiseMatchData& md = ctx.Details(0)->matches;
  std::optional<Eigen::Vector2d> px;
  for (int pass = 0; pass < 2 && !px; ++pass) {
    for (size_t i = 0; i < md.matches[p][f].size() && !px; ++i) {
      if (!md.match_inlier[p][f][i]) continue;
      const Eigen::Vector2d& pa = md.keypoints[f][a][md.matches[p][f][i].first];
      const std::vector<char>& checked = ctx.MatchCorrect(0, p, f);
      const bool correct = i < checked.size() && checked[i];
      if (pass == 1 || (correct && !ranges[a].empty() && SmoothRange(ranges[a], pa))) px = pa;
    }
  }
  if (!px) return nullptr;
  const AlignedEstimate& al = ctx.aligned[0];
  const std::vector<double> depths = EpipolarDepths(0.1, 1000.0, 24);
  Json st = {{"pair", p}, {"frame", f}, {"mode", ctx.run.results[0].semantic_mode}, {"px", {px->x(), px->y()}},
             {"depths", depths}};
  st["curve_truth"] = Curve(EpipolarCurve(cam_a, *px, cam_b, true_b_from_a, depths));
  const bool full_poses = al.cam_from_cam0[a] && al.cam_from_cam0[b] && !al.rotation_only[a] && !al.rotation_only[b];
  st["curve_estimate"] =
      full_poses ? Curve(EpipolarCurve(cam_a, *px, cam_b, *al.cam_from_cam0[b] * al.cam_from_cam0[a]->Inverse(), depths))
                 : Json(nullptr);
  const auto tp = ranges[a].empty() || ranges[b].empty()
                      ? std::nullopt
                      : TransferPixel(*px, cam_a, ranges[a], cam_b, ranges[b], true_b_from_a);
  st["true_point"] = tp ? Json({tp->x(), tp->y()}) : Json(nullptr);
  return st;
}

// One pair's entry of "pairs": its cameras, the true overlap and pose, and per mode the two-view
// outcome and the rig estimate's relative pose (aligned to the truth when it is known).
Json PairEntry(const ReportContext& ctx, size_t p, int a, int b, const std::optional<Rigid3d>& true_b_from_a,
               const std::string& data_file) {
  const CalibrationRun& run = ctx.run;
  const PairResult& first = run.results[0].pairwise.pairs.at(p);
  Json entry = {{"a", a}, {"b", b}, {"data", data_file}};
  const auto overlap = run.inputs.overlap.find({first.cam_a, first.cam_b});
  entry["overlap"] = overlap == run.inputs.overlap.end() ? Json(nullptr) : Json(overlap->second);
  entry["b_from_a_truth"] = true_b_from_a ? Pose(*true_b_from_a) : Json(nullptr);
  Json est = Json::object();
  for (size_t m = 0; m < run.modes.size(); ++m) {
    const PairResult& pr = run.results[m].pairwise.pairs.at(p);
    const CalibrationScores* truth = run.Truth(m);
    const PairAgainstTruth t = truth ? truth->pairs.at(p) : PairAgainstTruth{};
    Json mode = {{"matches", pr.two_view.num_matches},
                 {"inliers", pr.two_view.num_inliers},
                 {"success", pr.Solved()},
                 {"pair_type", pr.two_view.success ? Json(std::string(PairTypeName(pr.two_view.pair_type))) : Json(nullptr)},
                 {"failure_reason", pr.Solved() ? std::string() : PairStatus(pr)},
                 {"matches_correct", t.matches_correct},
                 {"matches_evaluated", t.matches_evaluated},
                 {"inliers_correct", t.inliers_correct},
                 {"inliers_evaluated", t.inliers_evaluated},
                 {"rotation_error_deg", json_io::OptionalNumber(t.rotation_error_deg)},
                 {"translation_direction_error_deg", json_io::OptionalNumber(t.translation_direction_error_deg)}};
    Json rig_pose = nullptr;
    if (ctx.HasTruth()) {
      const AlignedEstimate& al = ctx.aligned[m];
      if (al.cam_from_cam0[a] && al.cam_from_cam0[b] && !al.rotation_only[a] && !al.rotation_only[b]) {
        rig_pose = Pose(*al.cam_from_cam0[b] * al.cam_from_cam0[a]->Inverse());
      }
    } else if (const auto& pa = run.results[m].rig.cameras[a].cam_from_rig) {
      if (const auto& pb = run.results[m].rig.cameras[b].cam_from_rig) rig_pose = Pose(*pb * pa->Inverse());
    }
    mode["b_from_a_rig"] = rig_pose;
    est[run.results[m].semantic_mode] = mode;
  }
  entry["modes"] = est;
  return entry;
}

}  // namespace

Json WritePairs(ReportContext& ctx, Json* selftest) {
  const CalibrationRun& run = ctx.run;
  const Rig& rig = run.inputs.rig;
  const int n = ctx.NumCameras(), num_frames = ctx.NumFrames();
  const CalibrationReport& first = run.results.at(0).pairwise;
  // Pair data per pair index, filled frame by frame (each frame's ranges read once).
  std::vector<Json> pair_frames(first.pairs.size(), Json::array());
  std::vector<Rigid3d> true_b_from_a(first.pairs.size());
  for (size_t p = 0; p < first.pairs.size(); ++p) {
    const int a = rig.FindCamera(first.pairs[p].cam_a), b = rig.FindCamera(first.pairs[p].cam_b);
    if (ctx.run.inputs.truth) true_b_from_a[p] = *rig.cameras[b].cam_from_rig * rig.cameras[a].cam_from_rig->Inverse();
  }
  // The self-test's pair: the most inliers in the first mode, preferring a distorted camera A
  // (whose pixel the page must undistort), then a distorted B.
  int test_pair = -1, test_frame = -1;
  const RigCalibrationDetails* d0 = ctx.Details(0);
  if (ctx.HasTruth() && d0 && !d0->matches.match_inlier.empty()) {
    size_t best = 0;
    for (size_t p = 0; p < first.pairs.size(); ++p) {
      const int a = rig.FindCamera(first.pairs[p].cam_a), b = rig.FindCamera(first.pairs[p].cam_b);
      const size_t preference = rig.cameras[a].camera.model() != CameraModelId::kPinhole   ? 2
                                : rig.cameras[b].camera.model() != CameraModelId::kPinhole ? 1
                                                                                           : 0;
      for (int f = 0; f < num_frames; ++f) {
        size_t inliers = 0;
        for (char in : d0->matches.match_inlier[p][f]) inliers += in;
        if (inliers < 30) continue;  // too few to be the pair worth showing
        inliers += preference * 1000000;
        if (inliers > best) {
          best = inliers;
          test_pair = int(p);
          test_frame = f;
        }
      }
    }
  }
  std::optional<CapturePoses> capture_poses;
  if (ctx.HasTruth()) capture_poses.emplace(rig.cameras, run.inputs.frames);
  for (int f = 0; f < num_frames; ++f) {
    const std::vector<ImageF> ranges = ctx.HasTruth() ? FrameRanges(ctx, f) : std::vector<ImageF>(n);
    std::vector<ViewPose> poses(n);
    if (ctx.HasTruth()) {
      for (int c = 0; c < n; ++c) poses[c] = capture_poses->Of(rig.cameras[c], run.inputs.frames.frames[f]);
    }
    for (size_t p = 0; p < first.pairs.size(); ++p) {
      const int a = rig.FindCamera(first.pairs[p].cam_a), b = rig.FindCamera(first.pairs[p].cam_b);
      const Camera& cam_a = rig.cameras[a].camera;
      const Camera& cam_b = rig.cameras[b].camera;
      Json frame;
      const auto overlap = run.inputs.overlap.find({first.pairs[p].cam_a, first.pairs[p].cam_b});
      const bool may_overlap = overlap == run.inputs.overlap.end() || overlap->second > 0;
      if (ctx.HasTruth() && may_overlap && !ranges[a].empty() && !ranges[b].empty()) {
        const int gw_a = std::min(cam_a.width(), ctx.options.overlap_grid_width);
        const int gh_a = std::max(1, int(std::lround(double(cam_a.height()) * gw_a / cam_a.width())));
        const int gw_b = std::min(cam_b.width(), ctx.options.overlap_grid_width);
        const int gh_b = std::max(1, int(std::lround(double(cam_b.height()) * gw_b / cam_b.width())));
        frame["overlap"] = {
            {"a", {{"width", gw_a}, {"height", gh_a},
                   {"cells", Base64Of(OverlapGrid(cam_a, ranges[a], poses[a], cam_b, ranges[b], poses[b], gw_a, gh_a))}}},
            {"b", {{"width", gw_b}, {"height", gh_b},
                   {"cells", Base64Of(OverlapGrid(cam_b, ranges[b], poses[b], cam_a, ranges[a], poses[a], gw_b, gh_b))}}}};
      } else {
        frame["overlap"] = nullptr;
      }
      Json modes = Json::object();
      for (size_t m = 0; m < run.modes.size(); ++m) {
        const RigCalibrationDetails* d = ctx.Details(m);
        if (!d || d->matches.matches.empty()) continue;
        const PairwiseMatchData& md = d->matches;
        const auto& mt = md.matches.at(p).at(f);
        const std::vector<char>& correct = ctx.MatchCorrect(m, p, f);
        std::vector<float> xy_a, xy_b;
        std::vector<uint8_t> flags;
        for (size_t i = 0; i < mt.size(); ++i) {
          const Eigen::Vector2d& pa = md.keypoints.at(f).at(a).at(mt[i].first);
          const Eigen::Vector2d& pb = md.keypoints.at(f).at(b).at(mt[i].second);
          xy_a.insert(xy_a.end(), {float(pa.x()), float(pa.y())});
          xy_b.insert(xy_b.end(), {float(pb.x()), float(pb.y())});
          uint8_t fl = md.match_inlier[p][f][i] ? kInlier : 0;
          if (i < correct.size()) fl |= kChecked | (correct[i] ? kCorrect : 0);
          flags.push_back(fl);
        }
        modes[run.results[m].semantic_mode] = {
            {"count", mt.size()}, {"a", Base64Of(xy_a)}, {"b", Base64Of(xy_b)}, {"flags", Base64Of(flags)}};
      }
      frame["modes"] = modes;
      pair_frames[p].push_back(frame);

      if (int(p) == test_pair && f == test_frame && selftest) {
        *selftest = SelfTestReference(ctx, p, f, a, b, true_b_from_a[p], ranges);
      }
    }
  }
  Json pairs = Json::array();
  for (size_t p = 0; p < first.pairs.size(); ++p) {
    const int a = rig.FindCamera(first.pairs[p].cam_a), b = rig.FindCamera(first.pairs[p].cam_b);
    const std::string stem = "pair_c" + std::to_string(a) + "_c" + std::to_string(b);
    WriteDataScript(ctx.dir / "data" / (stem + ".js"), "pair/" + std::to_string(p), {{"frames", pair_frames[p]}});
    pairs.push_back(PairEntry(ctx, p, a, b, ctx.run.inputs.truth ? std::optional<Rigid3d>(true_b_from_a[p]) : std::nullopt,
                              "data/" + stem + ".js"));
  }
  return pairs;
}

}  // namespace rigsim::report_parts
