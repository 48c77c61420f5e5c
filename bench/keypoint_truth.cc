// rigsim_keypoint_truth DATASET [--drop RULE] [--max-octave K]: where the calibrator's unseen error
// on renders comes from. Runs the calibration of `rigsim calibrate --semantics none` in process
// on the keypoints it would detect (optionally thinned by a rule that reads the truth), then
// measures every inlier match it used against the ground truth (range images, true poses):
//  - per pair / temporal pair: the true error of each match (B's keypoint minus A's keypoint carried
//    into B with A's true range), its mean (bias), RMS, by keypoint octave, near a range
//    discontinuity or not, by view-angle change, and its mean per 4x4 image cell;
//  - per track observation: the residual at the TRUE poses (track triangulated from the true
//    poses), to compare with the bundle adjustment's reprojection RMS;
//  - the bundle adjustment started at the true poses on those tracks: where it moves each camera
//    (its rotation error) against the deviation it states, on all observations and with the truth's
//    suspects removed.
// A measuring tool, not a test: it needs a rendered dataset with depth/ and prints tables.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <Eigen/Geometry>

#include "calibrator/calibrate_rig.h"
#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/features/features.h"
#include "calibrator/model/tracks.h"
#include "dataset/capture_poses.h"
#include "dataset/dataset.h"
#include "dataset/ground_truth.h"
#include "dataset/image_io.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"
#include "pipeline/calibration_scores.h"

using namespace rigsim;

namespace {

constexpr double kDeg = 180.0 / M_PI;

int Octave(float size) { return int(std::floor(std::log2(std::max(size, 1.0f) / 1.6) + 1e-6)) - 1; }

// Largest relative change of the range within `radius` px of `px` (sky counts as infinite).
double Discontinuity(const ImageF& range, const Eigen::Vector2d& px, double radius) {
  const int x0 = int(std::lround(px.x())), y0 = int(std::lround(px.y())), r = int(std::ceil(radius));
  float lo = 1e30f, hi = 0.f;
  for (int y = y0 - r; y <= y0 + r; ++y) {
    for (int x = x0 - r; x <= x0 + r; ++x) {
      if (x < 0 || y < 0 || x >= range.width || y >= range.height) continue;
      if ((x - x0) * (x - x0) + (y - y0) * (y - y0) > radius * radius + 0.5) continue;
      const float v = range.at(x, y);
      if (v <= 0.f) return 1e9;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return hi > 0.f ? hi / lo - 1.0 : 1e9;
}

struct Stat {
  int n = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double sq = 0.0;
  int over1 = 0;
  void Add(const Eigen::Vector2d& e) {
    ++n;
    sum += e;
    sq += e.squaredNorm();
    over1 += e.norm() > 1.0;
  }
  std::string Str() const {
    if (n == 0) return "n=0";
    char b[160];
    std::snprintf(b, sizeof b, "n=%4d mean=(%+.3f,%+.3f) |mean|=%.3f rms=%.3f >1px=%4.1f%%", n, sum.x() / n, sum.y() / n,
                  (sum / n).norm(), std::sqrt(sq / n), 100.0 * over1 / n);
    return b;
  }
};

struct Args {
  std::string dataset;
  std::string drop = "none";  // none | edges | sky-edges
  double edge_threshold = 0.05;
  int max_octave = 99;
  int min_octave = -99;
  bool quiet = false;
};

}  // namespace

int main(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--drop" && i + 1 < argc) args.drop = argv[++i];
    else if (a == "--edge" && i + 1 < argc) args.edge_threshold = std::stod(argv[++i]);
    else if (a == "--max-octave" && i + 1 < argc) args.max_octave = std::stoi(argv[++i]);
    else if (a == "--min-octave" && i + 1 < argc) args.min_octave = std::stoi(argv[++i]);
    else if (a == "--quiet") args.quiet = true;
    else args.dataset = a;
  }
  if (args.dataset.empty()) {
    std::fprintf(stderr, "usage: %s DATASET [--drop none|edges] [--edge REL] [--max-octave K] [--min-octave K]\n", argv[0]);
    return 2;
  }
  const CalibrationInputs in = ReadCalibrationInputs(args.dataset);
  const Rig& truth = *in.truth;
  const DatasetLayout layout(args.dataset);
  const int nc = int(truth.cameras.size()), nf = int(in.frames.frames.size());
  const CapturePoses capture(truth.cameras, in.frames, layout.FramesJson().string());

  // Range images and true view poses.
  std::vector<ImageF> range(size_t(nc * nf));
  std::vector<ViewPose> pose(size_t(nc * nf));
  for (int c = 0; c < nc; ++c) {
    for (int f = 0; f < nf; ++f) {
      range[c * nf + f] = ReadImageF(layout.Depth(truth.cameras[c].name, in.frames.frames[f].name));
      pose[c * nf + f] = capture.Of(truth.cameras[c], in.frames.frames[f]);
    }
  }

  // Features as the pipeline detects them (defaults of `rigsim calibrate`), then thinned.
  CalibrationRunOptions run;
  run.rig.pairwise.num_threads = 1;
  run.rig.keep_details = true;
  std::vector<std::vector<FeatureSet>> det = DetectFeaturesInImages(
      nc * nf,
      [&](int image) {
        LabelledImage out;
        out.rgb = ReadImageU8(layout.Image(truth.cameras[image / nf].name, in.frames.frames[image % nf].name), 3);
        return out;
      },
      run.features, {nullptr}, 1);
  std::vector<FeatureSet> features = std::move(det[0]);
  int kept = 0, total = 0;
  for (int v = 0; v < nc * nf; ++v) {
    FeatureSet& fs = features[v];
    std::vector<int> keep;
    for (int k = 0; k < fs.size(); ++k) {
      const Keypoint& kp = fs.keypoints[k];
      const int oct = Octave(kp.size);
      bool ok = oct <= args.max_octave && oct >= args.min_octave;
      if (ok && args.drop == "edges") ok = Discontinuity(range[v], kp.px, std::max(2.0, 0.5 * kp.size)) < args.edge_threshold;
      if (ok) keep.push_back(k);
    }
    total += fs.size();
    kept += int(keep.size());
    FeatureSet out;
    out.kind = fs.kind;
    out.descriptor_size = fs.descriptor_size;
    for (int k : keep) {
      out.keypoints.push_back(fs.keypoints[k]);
      out.descriptors.insert(out.descriptors.end(), fs.descriptor(k), fs.descriptor(k) + fs.descriptor_size);
    }
    fs = std::move(out);
  }
  std::printf("keypoints kept %d of %d (drop=%s edge=%.3f octaves %d..%d)\n", kept, total, args.drop.c_str(),
              args.edge_threshold, args.min_octave, args.max_octave);

  RigViews views;
  for (const RigCamera& rc : truth.cameras) {
    views.camera_names.push_back(rc.name);
    views.cameras.push_back(rc.camera);
  }
  views.num_frames = nf;
  views.features = features;
  for (const Frame& frame : in.frames.frames) views.frame_times_s.push_back(frame.timestamp_s);
  for (const RigCamera& rc : truth.cameras) views.readout_bottom_to_top.push_back(rc.readout_bottom_to_top);
  PairwiseMatchData md;
  const RigCalibrationResult result = CalibrateRig(views, run.rig, &md);
  const CalibrationScores scores = ScorePoses(truth, in.frames, result);
  std::printf("calibration: reprojection RMS %.3f px, residual_correlation %.2f, %d observations\n",
              result.reprojection_rms_px, result.residual_correlation, result.num_observations);
  for (int c = 1; c < nc; ++c) {
    const CameraAgainstTruth& s = scores.cameras[c];
    const RigCameraStats& st = result.camera_stats[c];
    std::printf("  %s rot_err %.4f deg sd %.4f ratio %.1f | dir_err %.3f deg sd %.3f ratio %.1f | obs %d\n",
                truth.cameras[c].name.c_str(), s.rotation_error_deg.value_or(NAN), st.rotation_std_deg.value_or(NAN),
                s.rotation_sd_ratio.value_or(NAN), s.translation_direction_error_deg.value_or(NAN),
                st.direction_std_deg.value_or(NAN), s.direction_sd_ratio.value_or(NAN), st.observations);
  }

  // Every inlier match, pairs then temporal pairs: (view a, kp a, view b, kp b).
  struct Match {
    int va, ka, vb, kb;
    bool temporal;
    double err = 1e9;  // true error (px); 1e9: not transferable
    bool edge = false;
    int octave = 0;
  };
  std::vector<Match> matches;
  for (size_t p = 0; p < result.pairwise.pairs.size(); ++p) {
    const PairResult& pr = result.pairwise.pairs[p];
    if (!pr.two_view.success) continue;
    const int a = truth.FindCamera(pr.cam_a), b = truth.FindCamera(pr.cam_b);
    for (int f = 0; f < nf && p < md.inliers.size() && f < int(md.inliers[p].size()); ++f) {
      for (const auto& [ka, kb] : md.inliers[p][f]) matches.push_back({a * nf + f, ka, b * nf + f, kb, false});
    }
  }
  for (const TemporalPairEstimate& t : md.temporal) {
    if (!t.two_view.success) continue;
    for (const auto& [ka, kb] : t.inliers) matches.push_back({t.camera * nf + t.frame, ka, t.camera * nf + t.frame + 1, kb, true});
  }

  // True match errors.
  std::map<std::string, Stat> by;
  std::map<std::string, std::vector<Stat>> cells;  // 4x4 per (camera of B, kind)
  for (Match& m : matches) {
    const int ca = m.va / nf, cb = m.vb / nf;
    const Camera& cam_a = truth.cameras[ca].RenderedCamera();
    const Camera& cam_b = truth.cameras[cb].RenderedCamera();
    const Keypoint& kpa = features[m.va].keypoints[m.ka];
    const Keypoint& kpb = features[m.vb].keypoints[m.kb];
    const std::string kind = m.temporal ? "temporal " + truth.cameras[ca].name
                                        : truth.cameras[ca].name + "-" + truth.cameras[cb].name;
    const double ra = RangeAt(range[m.va], kpa.px);
    std::optional<Eigen::Vector2d> t;
    if (ra > 0) {
      t = TransferPixel(kpa.px, cam_a, range[m.va], pose[m.va], cam_b, range[m.vb], pose[m.vb]);
    }
    if (!t) {
      by[kind + " | untransferable (sky/occluded)"].Add(Eigen::Vector2d::Zero());
      continue;
    }
    const Eigen::Vector2d e = kpb.px - *t;
    const double disc = std::max(Discontinuity(range[m.va], kpa.px, std::max(2.0, 0.5 * kpa.size)),
                                 Discontinuity(range[m.vb], kpb.px, std::max(2.0, 0.5 * kpb.size)));
    const bool wrong = e.norm() > 2.0;
    m.err = e.norm();
    m.edge = disc >= 0.05;
    m.octave = std::max(Octave(kpa.size), Octave(kpb.size));
    by[kind + " | all"].Add(e);
    by[std::string(m.temporal ? "T" : "P") + " all | all"].Add(e);
    if (wrong) {
      by[kind + " | wrong (>2px)"].Add(e);
      continue;
    }
    by[kind + " | right (<=2px)"].Add(e);
    const std::string tag = m.temporal ? "T" : "P";
    by[tag + " right | edge " + std::string(disc >= 0.05 ? "yes" : "no ")].Add(e);
    char ob[64];
    std::snprintf(ob, sizeof ob, " right | octave %+d", std::max(Octave(kpa.size), Octave(kpb.size)));
    by[tag + ob].Add(e);
    // View-angle change: between the rays from A's and B's centres to the point.
    const Eigen::Vector3d ray_a = *cam_a.CamFromImg(kpa.px);
    const Rigid3d wa = pose[m.va].Row(RowOfPixel(kpa.px, cam_a)).Inverse();
    const Rigid3d wb = pose[m.vb].Row(RowOfPixel(kpb.px, cam_b)).Inverse();
    const Eigen::Vector3d X = wa * (ra * ray_a);
    const double ang = std::acos(std::clamp((X - wa.translation).normalized().dot((X - wb.translation).normalized()), -1.0, 1.0)) * kDeg;
    std::snprintf(ob, sizeof ob, " right | view change %s", ang < 2 ? "<2 deg" : ang < 5 ? "2-5 deg" : ang < 10 ? "5-10 deg" : ">10 deg");
    by[tag + ob].Add(e);
    {
      // The local affine map from A to B (the truth's transfer differentiated over 1 px): how
      // differently the two views foreshorten the surface at the keypoint.
      const auto at = [&](const Eigen::Vector2d& d) {
        return TransferPixel(kpa.px + d, cam_a, range[m.va], pose[m.va], cam_b, range[m.vb], pose[m.vb]);
      };
      const auto x0 = at({-1, 0}), x1 = at({1, 0}), y0 = at({0, -1}), y1 = at({0, 1});
      if (x0 && x1 && y0 && y1) {
        Eigen::Matrix2d J;
        J.col(0) = (*x1 - *x0) / 2;
        J.col(1) = (*y1 - *y0) / 2;
        const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix2d>(J).singularValues();
        const double aniso = sv(0) / std::max(sv(1), 1e-9) - 1.0;
        std::snprintf(ob, sizeof ob, " right | anisotropy %s", aniso < 0.05 ? "<0.05" : aniso < 0.15 ? "0.05-0.15" : aniso < 0.4 ? "0.15-0.4" : ">0.4");
        by[tag + ob].Add(e);
      }
    }
    const double scale = kpb.size / std::max(kpa.size, 0.1f);
    std::snprintf(ob, sizeof ob, " right | size ratio B/A %s", scale < 0.8 ? "<0.8" : scale < 1.25 ? "0.8-1.25" : ">1.25");
    by[tag + ob].Add(e);
    std::vector<Stat>& cell = cells[truth.cameras[cb].name + (m.temporal ? " temporal" : " pairs")];
    cell.resize(16);
    const int cx = std::clamp(int(4 * kpb.px.x() / cam_b.width()), 0, 3), cy = std::clamp(int(4 * kpb.px.y() / cam_b.height()), 0, 3);
    cell[cy * 4 + cx].Add(e);
  }
  std::printf("\nTrue error of inlier matches (B's keypoint minus A's carried into B, px):\n");
  for (const auto& [k, s] : by) std::printf("  %-44s %s\n", k.c_str(), s.Str().c_str());
  if (!args.quiet) {
    std::printf("\nMean true error per 4x4 cell of B (right matches; x,y px; n):\n");
    for (const auto& [k, cs] : cells) {
      std::printf("  %s\n", k.c_str());
      for (int y = 0; y < 4; ++y) {
        std::printf("   ");
        for (int x = 0; x < 4; ++x) {
          const Stat& s = cs[y * 4 + x];
          if (s.n) std::printf(" (%+.2f,%+.2f;%3d)", s.sum.x() / s.n, s.sum.y() / s.n, s.n);
          else std::printf(" %20s", "-");
        }
        std::printf("\n");
      }
    }
  }

  // Tracks from the same inliers (a filter decides per match); residuals at the true poses; the
  // adjustment started at the truth.
  RigPoses tp;
  const Rigid3d world_from_rig0 = in.frames.frames[0].rig_from_world->Inverse();
  for (int c = 0; c < nc; ++c) tp.cam_from_rig.push_back(*truth.cameras[c].cam_from_rig);
  for (int f = 0; f < nf; ++f) tp.rig_from_world.push_back(*in.frames.frames[f].rig_from_world * world_from_rig0);
  // rearrange: 0 the keypoints as detected; 1 each observation at its track's point (triangulated
  // from the true poses) projected, plus its own residual there (a check: as detected); 2 plus
  // another observation's residual (shuffled over all); 3 plus its own residual with a random sign.
  const auto experiment = [&](const char* label, const std::function<bool(const Match&)>& keep, double synthetic_noise_px,
                              int seed, int rearrange = 0, PerCamera<Rigid3d>* adjusted = nullptr,
                              PerCamera<double>* stated_sd = nullptr) {
    std::vector<PairMatches> pm;
    std::vector<TemporalPairEstimate> temporal = md.temporal;
    size_t i = 0;
    for (size_t p = 0; p < result.pairwise.pairs.size(); ++p) {
      const PairResult& pr = result.pairwise.pairs[p];
      if (!pr.two_view.success) continue;
      PairMatches one{truth.FindCamera(pr.cam_a), truth.FindCamera(pr.cam_b), {}};
      one.per_frame.resize(nf);
      for (int f = 0; f < nf && p < md.inliers.size() && f < int(md.inliers[p].size()); ++f) {
        for (const auto& ab : md.inliers[p][f]) {
          if (keep(matches[i++])) one.per_frame[f].push_back(ab);
        }
      }
      pm.push_back(one);
    }
    for (TemporalPairEstimate& t : temporal) {
      if (!t.two_view.success) continue;
      std::vector<std::pair<int, int>> kept_inliers;
      for (const auto& ab : t.inliers) {
        if (keep(matches[i++])) kept_inliers.push_back(ab);
      }
      t.inliers = kept_inliers;
    }
    const std::vector<ViewTrack> tracks = BuildViewTracks(nc, nf, pm, temporal);
    FrameKeypoints kps = md.keypoints;
    if (synthetic_noise_px >= 0) {
      // Every track's observations made exact (its first keypoint lifted with its true range and
      // projected with the true poses), plus independent Gaussian noise.
      std::mt19937 rng(seed);
      std::normal_distribution<double> g(0.0, synthetic_noise_px);
      for (const ViewTrack& tr : tracks) {
        const ViewObservation& o0 = tr.observations[0];
        const int v0 = o0.camera * nf + o0.frame;
        const Eigen::Vector2d px0 = md.keypoints[o0.frame][o0.camera][o0.keypoint];
        const double r0 = RangeAt(range[v0], px0);
        const Rigid3d wf0 = tp.CamFromWorld(o0.camera, o0.frame).Inverse();
        const Eigen::Vector3d X = r0 > 0 ? Eigen::Vector3d(wf0 * (r0 * *truth.cameras[o0.camera].camera.CamFromImg(px0)))
                                         : Eigen::Vector3d(wf0 * (1e5 * *truth.cameras[o0.camera].camera.CamFromImg(px0)));
        for (const ViewObservation& o : tr.observations) {
          const std::optional<Eigen::Vector2d> px = truth.cameras[o.camera].camera.ImgFromCam(tp.CamFromWorld(o.camera, o.frame) * X);
          if (px) kps[o.frame][o.camera][o.keypoint] = *px + Eigen::Vector2d(g(rng), g(rng));
        }
      }
    }
    if (rearrange > 0) {
      struct Slot {
        int f, c, k;
        Eigen::Vector2d exact, residual;
        bool multi;
      };
      std::vector<Slot> slots;
      for (const ViewTrack& tr : tracks) {
        std::vector<Eigen::Vector3d> o, d;
        bool multi = false;
        for (const ViewObservation& ob : tr.observations) {
          const Rigid3d wfc = tp.CamFromWorld(ob.camera, ob.frame).Inverse();
          o.push_back(wfc.translation);
          d.push_back(wfc.rotation * *truth.cameras[ob.camera].camera.CamFromImg(kps[ob.frame][ob.camera][ob.keypoint]));
          multi = multi || ob.camera != tr.observations[0].camera;
        }
        const std::optional<Eigen::Vector3d> X = TriangulateRays(o, d, 0.25 / kDeg);
        if (!X) continue;
        for (const ViewObservation& ob : tr.observations) {
          const std::optional<Eigen::Vector2d> px = truth.cameras[ob.camera].camera.ImgFromCam(tp.CamFromWorld(ob.camera, ob.frame) * *X);
          if (!px) continue;
          const Eigen::Vector2d r = kps[ob.frame][ob.camera][ob.keypoint] - *px;
          if (r.norm() > 3.0) continue;
          slots.push_back({ob.frame, ob.camera, ob.keypoint, *px, r, multi});
        }
      }
      std::mt19937 rng(seed);
      std::vector<size_t> perm(slots.size());
      for (size_t j = 0; j < perm.size(); ++j) perm[j] = j;
      if (rearrange == 2) std::shuffle(perm.begin(), perm.end(), rng);
      for (size_t j = 0; j < slots.size(); ++j) {
        Eigen::Vector2d r = slots[perm[j]].residual;
        // 4: random sign on the one-camera tracks only; 5: on the tracks across cameras only.
        const bool flip = rearrange == 3 || (rearrange == 4 && !slots[j].multi) || (rearrange == 5 && slots[j].multi);
        if (flip && (rng() & 1)) r = -r;
        kps[slots[j].f][slots[j].c][slots[j].k] = slots[j].exact + r;
      }
    }
    Stat at_truth;
    for (const ViewTrack& tr : tracks) {
      std::vector<Eigen::Vector3d> o, d;
      std::vector<std::pair<Rigid3d, Eigen::Vector2d>> views_px;
      for (const ViewObservation& ob : tr.observations) {
        const Rigid3d cfw = tp.CamFromWorld(ob.camera, ob.frame);
        const Eigen::Vector2d px = kps[ob.frame][ob.camera][ob.keypoint];
        const Rigid3d wfc = cfw.Inverse();
        o.push_back(wfc.translation);
        d.push_back(wfc.rotation * *truth.cameras[ob.camera].camera.CamFromImg(px));
        views_px.push_back({cfw, px});
      }
      const std::optional<Eigen::Vector3d> X = TriangulateRays(o, d, 0.25 / kDeg);
      if (!X) continue;
      for (size_t k = 0; k < views_px.size(); ++k) {
        const std::optional<Eigen::Vector2d> px = truth.cameras[tr.observations[k].camera].camera.ImgFromCam(views_px[k].first * *X);
        if (px && (views_px[k].second - *px).norm() <= 3.0) at_truth.Add(views_px[k].second - *px);
      }
    }
    RigBundleAdjustmentOptions bo;
    const MultiFrameBundleAdjustmentResult ba = MultiFrameRigBundleAdjust(views.cameras, kps, tracks, tp, 1, bo);
    if (adjusted) *adjusted = ba.poses.cam_from_rig;
    if (stated_sd) *stated_sd = ba.rotation_stddev_deg;
    std::printf("%-34s tracks %5zu residuals at truth rms %.3f | adjusted from truth: RMS %.3f px, %d obs, corr %.2f |", label,
                tracks.size(), std::sqrt(at_truth.sq / std::max(at_truth.n, 1)), ba.reprojection_rms_px, ba.num_observations,
                ba.residual_correlation);
    for (int c = 1; c < nc; ++c) {
      if (!ba.poses.cam_from_rig[c]) continue;
      const double err = ba.poses.cam_from_rig[c]->rotation.angularDistance(tp.cam_from_rig[c]->rotation) * kDeg;
      const Eigen::Vector3d ce = ba.poses.cam_from_rig[c]->SourceOriginInTarget();
      const Eigen::Vector3d ct = tp.cam_from_rig[c]->SourceOriginInTarget();
      const double derr = std::acos(std::clamp(ce.normalized().dot(ct.normalized()), -1.0, 1.0)) * kDeg;
      const double sd = ba.rotation_stddev_deg[c].value_or(NAN);
      std::printf(" %s %.3f/%.3f=%.1f dir %.2f", truth.cameras[c].name.c_str(), err, sd, err / sd, derr);
    }
    std::printf("\n");
  };
  std::printf("\nBundle adjustment started at the true poses on the inliers' tracks (per camera: rotation moved / stated sd = ratio, deg; direction moved, deg):\n");
  experiment("all inliers", [](const Match&) { return true; }, -1, 0);
  experiment("drop wrong (>2 px true)", [](const Match& m) { return m.err <= 2.0; }, -1, 0);
  experiment("drop >1 px true", [](const Match& m) { return m.err <= 1.0; }, -1, 0);
  experiment("drop >0.5 px true", [](const Match& m) { return m.err <= 0.5; }, -1, 0);
  experiment("drop untransferable+wrong+edges", [](const Match& m) { return m.err <= 2.0 && !m.edge; }, -1, 0);
  experiment("octave -1 only (and <=2 px)", [](const Match& m) { return m.err <= 2.0 && m.octave <= -1; }, -1, 0);
  experiment("octave >=0 only (and <=2 px)", [](const Match& m) { return m.err <= 2.0 && m.octave >= 0; }, -1, 0);
  for (int seed = 1; seed <= 3; ++seed) {
    char label[64];
    std::snprintf(label, sizeof label, "exact + 0.25 px noise, seed %d", seed);
    experiment(label, [](const Match&) { return true; }, 0.25, seed);
  }
  for (int seed = 1; seed <= 2; ++seed) {
    char label[64];
    std::snprintf(label, sizeof label, "exact(<=2px) + 0.25 px noise, seed %d", seed);
    experiment(label, [](const Match& m) { return m.err <= 2.0; }, 0.25, seed);
  }
  {
    // Residuals at the true poses by kind of observation: is the error the same everywhere?
    std::map<std::string, Stat> groups;
    const std::vector<ViewTrack> all_tracks = BuildViewTracks(nc, nf, [&] {
      std::vector<PairMatches> pm;
      for (size_t p = 0; p < result.pairwise.pairs.size(); ++p) {
        const PairResult& pr = result.pairwise.pairs[p];
        if (pr.two_view.success && p < md.inliers.size()) pm.push_back({truth.FindCamera(pr.cam_a), truth.FindCamera(pr.cam_b), md.inliers[p]});
      }
      return pm;
    }(), md.temporal);
    for (const ViewTrack& tr : all_tracks) {
      std::vector<Eigen::Vector3d> o, d;
      bool multi = false;
      for (const ViewObservation& ob : tr.observations) {
        const Rigid3d wfc = tp.CamFromWorld(ob.camera, ob.frame).Inverse();
        o.push_back(wfc.translation);
        d.push_back(wfc.rotation * *truth.cameras[ob.camera].camera.CamFromImg(md.keypoints[ob.frame][ob.camera][ob.keypoint]));
        multi = multi || ob.camera != tr.observations[0].camera;
      }
      const std::optional<Eigen::Vector3d> X = TriangulateRays(o, d, 0.25 / kDeg);
      if (!X) continue;
      for (const ViewObservation& ob : tr.observations) {
        const Camera& cam = truth.cameras[ob.camera].camera;
        const Eigen::Vector3d xc = tp.CamFromWorld(ob.camera, ob.frame) * *X;
        const std::optional<Eigen::Vector2d> px = cam.ImgFromCam(xc);
        if (!px) continue;
        const Eigen::Vector2d kp = md.keypoints[ob.frame][ob.camera][ob.keypoint];
        const Eigen::Vector2d r = kp - *px;
        if (r.norm() > 3.0) continue;
        const double rad = std::hypot((kp.x() - cam.cx()) / cam.cx(), (kp.y() - cam.cy()) / cam.cy()) / std::sqrt(2.0);
        const double depth = xc.norm();
        const int len = int(tr.observations.size());
        groups[std::string("track ") + (multi ? "across cameras" : "one camera")].Add(r);
        groups[std::string("radius ") + (rad < 0.4 ? "<0.4" : rad < 0.7 ? "0.4-0.7" : ">0.7")].Add(r);
        groups[std::string("depth ") + (depth < 5 ? "<5 m" : depth < 15 ? "5-15 m" : depth < 40 ? "15-40 m" : ">40 m")].Add(r);
        groups[std::string("track length ") + (len == 2 ? "2" : len <= 4 ? "3-4" : "5+")].Add(r);
        groups["camera " + truth.cameras[ob.camera].name].Add(r);
        const Keypoint& k = features[ob.camera * nf + ob.frame].keypoints[ob.keypoint];
        char ob_s[32];
        std::snprintf(ob_s, sizeof ob_s, "octave %+d", std::min(Octave(k.size), 2));
        groups[ob_s].Add(r);
      }
    }
    std::printf("\nResiduals at the true poses by kind of observation:\n");
    for (const auto& [k, st] : groups) std::printf("  %-26s %s\n", k.c_str(), st.Str().c_str());
  }
  for (int seed = 1; seed <= 3; ++seed) {
    char label[64];
    std::snprintf(label, sizeof label, "random half of the matches, seed %d", seed);
    experiment(label, [seed](const Match& m) { return (std::hash<long>()(long(m.va) * 1000003L + m.ka * 7919L + seed * 104729L) >> 3) % 2 == 0; }, -1, 0);
  }
  for (int seed = 1; seed <= 3; ++seed) {
    char label[64];
    std::snprintf(label, sizeof label, "sign kept across cameras only, %d", seed);
    experiment(label, [](const Match&) { return true; }, -1, seed, 4);
    std::snprintf(label, sizeof label, "sign kept in one camera only, %d", seed);
    experiment(label, [](const Match&) { return true; }, -1, seed, 5);
  }
  // Leave one group of same-instant matches out at a time (delete-a-group jackknife): the spread
  // of the cameras' rotations over those adjustments against the error, from the images alone.
  PerCamera<Rigid3d> full;
  PerCamera<double> full_sd;
  experiment("all inliers (jackknife reference)", [](const Match&) { return true; }, -1, 0, 0, &full, &full_sd);
  const auto jackknife = [&](const char* name, int groups, const std::function<int(const Match&)>& group_of) {
    std::vector<PerCamera<Rigid3d>> loo(static_cast<size_t>(groups));
    for (int k = 0; k < groups; ++k) {
      char label[64];
      std::snprintf(label, sizeof label, "  without %s %d", name, k);
      experiment(label, [&, k](const Match& m) { return group_of(m) != k; }, -1, 0, 0, &loo[k]);
    }
    for (int c = 1; c < nc; ++c) {
      if (!full[c]) continue;
      std::vector<Eigen::Vector3d> d;
      for (int k = 0; k < groups; ++k) {
        if (!loo[k][c]) continue;
        const Eigen::AngleAxisd aa(loo[k][c]->rotation * full[c]->rotation.conjugate());
        d.push_back(aa.angle() * aa.axis() * kDeg);
      }
      const int n = int(d.size());
      if (n < 2) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& v : d) mean += v / n;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const auto& v : d) cov += (v - mean) * (v - mean).transpose() * double(n - 1) / n;
      const double jsd = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues().maxCoeff());
      const double err = full[c]->rotation.angularDistance(tp.cam_from_rig[c]->rotation) * kDeg;
      std::printf("  jackknife over %s, %s: rotation error %.3f deg, stated sd %.4f (ratio %.1f), jackknife sd over %d groups %.4f (ratio %.1f)\n",
                  name, truth.cameras[c].name.c_str(), err, full_sd[c].value_or(NAN), err / full_sd[c].value_or(NAN), n, jsd,
                  err / jsd);
    }
  };
  jackknife("frames' pairs", nf, [nf](const Match& m) { return m.temporal ? -1 : m.va % nf; });
  jackknife("row bands of pair matches", 4, [&](const Match& m) {
    return m.temporal ? -1 : std::clamp(int(4 * features[m.va].keypoints[m.ka].px.y() / truth.cameras[m.va / nf].camera.height()), 0, 3);
  });
  jackknife("random eighths of all matches", 8, [](const Match& m) {
    return int((std::hash<long>()(long(m.va) * 1000003L + m.ka * 7919L) >> 3) % 8);
  });
  {
    // Monte Carlo of the covariance on these tracks: exact observations plus independent 0.25 px
    // noise, many draws; the spread of the rotations against the stated sd.
    constexpr int kDraws = 16;
    std::vector<PerCamera<Rigid3d>> draws(kDraws);
    std::vector<PerCamera<double>> sds(kDraws);
    for (int k = 0; k < kDraws; ++k) {
      char label[64];
      std::snprintf(label, sizeof label, "monte carlo draw %d", k);
      experiment(label, [](const Match&) { return true; }, 0.25, 100 + k, 0, &draws[k], &sds[k]);
    }
    for (int c = 1; c < nc; ++c) {
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      double sd_sum = 0.0, err_sum = 0.0;
      int n = 0;
      for (int k = 0; k < kDraws; ++k) {
        if (!draws[k][c] || !sds[k][c]) continue;
        const Eigen::AngleAxisd aa(draws[k][c]->rotation * tp.cam_from_rig[c]->rotation.conjugate());
        const Eigen::Vector3d v = aa.angle() * aa.axis() * kDeg;
        cov += v * v.transpose();
        sd_sum += *sds[k][c];
        err_sum += aa.angle() * kDeg / *sds[k][c];
        ++n;
      }
      if (n < 2) continue;
      cov /= n;
      const double emp = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues().maxCoeff());
      std::printf("  monte carlo %s: %d draws, empirical sd (worst axis, about the truth) %.4f deg, stated sd mean %.4f, mean error/sd %.2f\n",
                  truth.cameras[c].name.c_str(), n, emp, sd_sum / n, err_sum / n);
    }
  }
  experiment("own residuals at truth, in place", [](const Match&) { return true; }, -1, 1, 1);
  for (int seed = 1; seed <= 3; ++seed) {
    char label[64];
    std::snprintf(label, sizeof label, "residuals shuffled, seed %d", seed);
    experiment(label, [](const Match&) { return true; }, -1, seed, 2);
    std::snprintf(label, sizeof label, "residuals random sign, seed %d", seed);
    experiment(label, [](const Match&) { return true; }, -1, seed, 3);
  }
  return 0;
}
