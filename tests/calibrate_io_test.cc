// `rigsim calibrate` inputs and outputs through the built binary: the label sources
// (truth, a user folder in Cityscapes ids or colours, the segmentation-noise model) and the
// files written per semantic mode (rig.json, Kalibr camchain.yaml, OpenCV YAML, COLMAP text
// model, pairs.json), read back with their consumers' conventions.
//
// The dataset: the built-in street through a 3-camera ring placed by `make-rig --scene` (320x240,
// 2 frames), plus a camera "back" that faces backwards and overlaps no other camera, so that one
// camera cannot be calibrated.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "geometry/rig.h"
#include "pipeline/calibration_run.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

#ifndef RIGSIM_SOURCE_DIR
#error "RIGSIM_SOURCE_DIR must name the source tree"
#endif

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json ReadJson(const fs::path& path) { return json::parse(ReadFile(path)); }

// Data lines of a COLMAP text file: neither comments nor empty lines.
std::vector<std::string> DataLines(const fs::path& path) {
  std::vector<std::string> lines;
  std::istringstream in(ReadFile(path));
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  return lines;
}


class CalibrateIo : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    base_ = new TempDir();
    const std::string scene = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";
    const fs::path rig_json = *base_ / "rig.json", frames_json = *base_ / "frames.json";
    CliResult r = RunRigsim({"make-rig", "ring", "--cameras", "3", "--spacing", "50", "--hfov", "90", "--width", "320", "--height",
                    "240", "--frames", "2", "--step", "1", "--scene", scene, "--rig-out", rig_json.string(),
                    "--frames-out", frames_json.string()},
                   *base_ / "make_rig");
    ASSERT_EQ(r.code, 0) << r.err;
    Rig rig = ReadRig(rig_json);
    RigCamera back = rig.cameras[0];
    back.name = "back";
    // Looks along the rig's -z, from the back of the ring: shares nothing with the others.
    const Eigen::Matrix3d r_back = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
    back.cam_from_rig = Rigid3d(r_back, -r_back * Eigen::Vector3d(0, 0, -0.5));
    rig.cameras.push_back(back);
    WriteRig(rig, rig_json);
    r = RunRigsim({"render", "--scene", scene, "--rig", rig_json.string(), "--frames", frames_json.string(), "--out",
             dataset().string(), "--spp", "1"},
            *base_ / "render");
    ASSERT_EQ(r.code, 0) << r.err;
  }
  static void TearDownTestSuite() { delete base_; }

  static fs::path dataset() { return *base_ / "dataset"; }
  // The fixture's rig has `back`, which shares nothing with the others: calibrate writes every
  // result and exits with 3, naming it.
  static void ExpectBackUncalibrated(const CliResult& r) {
    ASSERT_EQ(r.code, 3) << r.err;
    const size_t list = r.err.find("rigsim: not every camera was calibrated (");
    ASSERT_NE(list, std::string::npos) << r.err;
    // back among the cameras named (another may join it: this small ring's directions are loose).
    const size_t end = r.err.find(')', list);
    EXPECT_NE(r.err.substr(list, end - list).find("back"), std::string::npos) << r.err;
  }
  // The dataset's images and rig.json alone in <dir_>/photos: photos without labels.
  fs::path PhotosWithoutLabels() {
    const fs::path photos = dir_ / "photos";
    fs::create_directories(photos);
    fs::copy(dataset() / "images", photos / "images", fs::copy_options::recursive);
    fs::copy_file(dataset() / "rig.json", photos / "rig.json");
    return photos;
  }
  CliResult Calibrate(std::vector<std::string> extra, const fs::path& out) {
    std::vector<std::string> args = {"calibrate", dataset().string(), "--out", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    if (std::find(args.begin(), args.end(), "--threads") == args.end()) args.insert(args.end(), {"--threads", "2"});
    return RunRigsim(args, dir_ / ("run" + std::to_string(runs_++)));
  }
  // A label folder <dir_>/<name>/<cam>/<frame>.png from the truth, transformed by `make`.
  template <typename F>
  fs::path LabelFolder(const std::string& name, F make) {
    const DatasetLayout layout(dataset());
    const Rig rig = ReadRig(layout.RigJson());
    for (const RigCamera& rc : rig.cameras) {
      for (const Frame& f : ReadFrames(layout.FramesJson()).frames) {
        const fs::path p = dir_ / name / rc.name / (f.name + ".png");
        fs::create_directories(p.parent_path());
        WriteImage(p, make(ReadLabelImage(layout.Label(rc.name, f.name)), rc.name, f.name));
      }
    }
    return dir_ / name;
  }
  // `rigsim calibrate` with `extra` fails with a message starting with `file` (when not empty)
  // and saying `part`, and leaves no output.
  void ExpectCalibrateFails(const std::vector<std::string>& extra, const std::string& file, const std::string& part) {
    const fs::path out = dir_ / "out";
    const CliResult r = Calibrate(extra, out);
    EXPECT_NE(r.code, 0) << r.err;
    if (!file.empty()) {
      EXPECT_NE(r.err.find("error: " + file + ": "), std::string::npos) << "message does not start with the file: " << r.err;
    }
    EXPECT_NE(r.err.find(part), std::string::npos) << "message does not say '" << part << "': " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(StagingFolders(out).empty());
  }

  static TempDir* base_;  // the shared dataset
  const TempDir dir_;     // each test's outputs
  int runs_ = 0;
};
TempDir* CalibrateIo::base_ = nullptr;

TEST_F(CalibrateIo, WritesEveryExportAndPairStatisticsPerMode) {
  const fs::path out = dir_ / "out";
  const CliResult r = Calibrate({"--semantics", "none,mask"}, out);
  ExpectBackUncalibrated(r);
  EXPECT_NE(r.err.find("warning: none: camchain.yaml, opencv.yaml and colmap/ leave out the cameras without a full "
                       "pose: back"),
            std::string::npos)
      << r.err;
  const json evaluation = ReadJson(out / "evaluation.json");
  EXPECT_EQ(evaluation["label_source"]["kind"], "truth");
  EXPECT_EQ(evaluation["label_source"]["used"], true);
  for (const std::string mode : {"none", "mask"}) {
    SCOPED_TRACE(mode);
    const fs::path dir = out / mode;
    // rig.json: every camera, "back" without a pose.
    const Rig rig = ReadRig(dir / "rig.json");
    ASSERT_EQ(rig.cameras.size(), 4u);
    std::vector<const RigCamera*> calibrated;
    for (const RigCamera& rc : rig.cameras) {
      if (rc.cam_from_rig) calibrated.push_back(&rc);
    }
    ASSERT_EQ(calibrated.size(), 3u) << "cam0..cam2 calibrated, back not";
    EXPECT_FALSE(rig.cameras[3].cam_from_rig.has_value());

    // Kalibr: one entry per calibrated camera, a T_cn_cnm1 for all but the first.
    const std::string camchain = ReadFile(dir / "camchain.yaml");
    for (int i = 0; i < 3; ++i) {
      EXPECT_NE(camchain.find("\ncam" + std::to_string(i) + ":\n"), std::string::npos) << camchain;
      EXPECT_NE(camchain.find("rostopic: /" + calibrated[i]->name + "/image_raw"), std::string::npos);
    }
    EXPECT_EQ(camchain.find("cam3:"), std::string::npos);
    EXPECT_EQ(camchain.find("/back/"), std::string::npos);
    size_t chain = 0;
    for (size_t p = camchain.find("\n  T_cn_cnm1:"); p != std::string::npos; p = camchain.find("\n  T_cn_cnm1:", p + 1)) ++chain;
    EXPECT_EQ(chain, 2u);

    // OpenCV: cv::FileStorage reads it; R, T are the estimate's cam_from_rig.
    cv::FileStorage fs_in((dir / "opencv.yaml").string(), cv::FileStorage::READ);
    ASSERT_TRUE(fs_in.isOpened());
    EXPECT_EQ(int(fs_in["num_cameras"]), 3);
    const cv::FileNode cams = fs_in["cameras"];
    ASSERT_EQ(cams.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      const cv::FileNode c = cams[i];
      EXPECT_EQ(std::string(c["name"]), calibrated[i]->name);
      cv::Mat k, d, rot, t;
      c["camera_matrix"] >> k;
      c["distortion_coefficients"] >> d;
      c["R"] >> rot;
      c["T"] >> t;
      ASSERT_EQ(k.rows, 3);
      ASSERT_EQ(rot.rows, 3);
      ASSERT_EQ(t.rows, 3);
      EXPECT_EQ(k.at<double>(0, 0), calibrated[i]->camera.params()[0]);
      const Eigen::Matrix3d r_est = calibrated[i]->cam_from_rig->RotationMatrix();
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(t.at<double>(a, 0), calibrated[i]->cam_from_rig->translation[a], 1e-12);
        for (int b = 0; b < 3; ++b) EXPECT_NEAR(rot.at<double>(a, b), r_est(a, b), 1e-12);
      }
    }

    // COLMAP: 3 cameras, an image per camera and frame (both frames have a rig pose), no points;
    // cx, cy + 0.5.
    const json& outputs = evaluation["methods"][mode]["outputs"];
    EXPECT_EQ(outputs["colmap_frames"], json({"000000", "000001"}));
    EXPECT_TRUE(outputs["colmap_frames_omitted"].empty());
    const std::vector<std::string> cameras_txt = DataLines(dir / "colmap" / "cameras.txt");
    const std::vector<std::string> images_txt = DataLines(dir / "colmap" / "images.txt");
    ASSERT_EQ(cameras_txt.size(), 3u);
    ASSERT_EQ(images_txt.size(), 6u);
    EXPECT_TRUE(DataLines(dir / "colmap" / "points3D.txt").empty());
    for (int i = 0; i < 3; ++i) {
      std::istringstream cam(cameras_txt[i]);
      int id, w, h;
      std::string model;
      double fx, fy, cx, cy;
      cam >> id >> model >> w >> h >> fx >> fy >> cx >> cy;
      EXPECT_EQ(id, i + 1);
      EXPECT_EQ(model, std::string(CameraModelName(calibrated[i]->camera.model())));
      EXPECT_DOUBLE_EQ(cx, calibrated[i]->camera.params()[2] + 0.5);
      // Image ids camera by camera, each camera's frames in order (what COLMAP's feature_extractor gives).
      const std::string name = images_txt[2 * i].substr(images_txt[2 * i].rfind(' ') + 1);
      EXPECT_EQ(name, calibrated[i]->name + "/000000.png");
      EXPECT_TRUE(fs::exists(dataset() / "images" / name));
    }
    const std::string first = images_txt[0];
    EXPECT_EQ(first.substr(0, first.find(" 1 cam0/")), "1 1 0 0 0 0 0 0") << "cam0 is the rig frame";
    // cam0 at frame 1 (image 2): its centre in the calibration's world (cam0 at frame 0) is the
    // rig's motion, which must agree with the truth in direction and, in units of cam1's distance
    // from cam0, in length.
    std::istringstream moved(images_txt[1]);
    int image_id, camera_id;
    double qw, qx, qy, qz, tx, ty, tz;
    std::string moved_name;
    moved >> image_id >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> camera_id >> moved_name;
    EXPECT_EQ(moved_name, "cam0/000001.png");
    const Rigid3d moved_from_world(Eigen::Quaterniond(qw, qx, qy, qz), Eigen::Vector3d(tx, ty, tz));
    const Eigen::Vector3d motion = moved_from_world.SourceOriginInTarget();
    const DatasetLayout layout(dataset());
    const Rig truth = ReadRig(layout.RigJson());
    const FramesFile truth_frames = ReadFrames(layout.FramesJson());
    const Rigid3d true_world = *truth.cameras[0].cam_from_rig * *truth_frames.frames[0].rig_from_world;
    const Eigen::Vector3d true_motion =
        true_world * (*truth.cameras[0].cam_from_rig * *truth_frames.frames[1].rig_from_world).SourceOriginInTarget();
    const double true_unit = (*truth.cameras[1].cam_from_rig * truth.cameras[0].cam_from_rig->Inverse())
                                 .SourceOriginInTarget()
                                 .norm();
    EXPECT_LT(AngleBetweenDeg(motion, true_motion), 3.0) << motion.transpose() << " vs " << true_motion.transpose();
    EXPECT_NEAR(motion.norm() * true_unit, true_motion.norm(), 0.1 * true_motion.norm());

    // rig_topdown.svg: every camera's true centre, an estimated one for the three calibrated, and
    // it is listed among the outputs.
    const std::string svg = ReadFile(dir / "rig_topdown.svg");
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    for (const RigCamera& rc : rig.cameras) {
      EXPECT_NE(svg.find("class=\"truth\" data-camera=\"" + rc.name + "\""), std::string::npos) << rc.name;
      EXPECT_EQ(svg.find("class=\"estimate\" data-camera=\"" + rc.name + "\"") != std::string::npos,
                rc.cam_from_rig.has_value())
          << rc.name;
    }
    EXPECT_TRUE(evaluation["methods"][mode]["rig"]["summary"]["max_rotation_error_deg"].is_number());
    const json files = evaluation["methods"][mode]["outputs"]["files"];
    EXPECT_NE(std::find(files.begin(), files.end(), "rig_topdown.svg"), files.end()) << files.dump();

    // pairs.json: all 6 pairs, with type, counts, residuals and errors against the truth.
    const json pairs = ReadJson(dir / "pairs.json");
    EXPECT_EQ(pairs["semantic_mode"], mode);
    EXPECT_EQ(pairs["label_source"]["kind"], "truth");
    ASSERT_EQ(pairs["pairs"].size(), 6u);
    std::set<std::string> solved;
    for (const json& p : pairs["pairs"]) {
      const std::string name = p["cam_a"].get<std::string>() + "-" + p["cam_b"].get<std::string>();
      SCOPED_TRACE(name);
      const std::string type = p["pair_type"];
      EXPECT_TRUE(type == "general" || type == "planar" || type == "rotation-only" || type == "failed") << type;
      EXPECT_GE(p["matches"].get<int>(), p["inliers"].get<int>());
      EXPECT_TRUE(p["overlap"].is_number());
      ASSERT_TRUE(p["rig_edge"].is_object());
      if (type == "general" || type == "planar") {
        solved.insert(name);
        EXPECT_GT(p["inliers"].get<int>(), 20);
        EXPECT_LT(p["median_residual_deg"].get<double>(), 0.5);
        EXPECT_LT(p["rotation_error_deg"].get<double>(), 2.0);
        EXPECT_TRUE(p["translation_direction_error_deg"].is_number());
      } else {
        EXPECT_TRUE(p["rotation_error_deg"].is_null());
      }
      if (name.find("back") != std::string::npos) {
        EXPECT_EQ(type, "failed");
        EXPECT_FALSE(p["rig_edge"]["used"].get<bool>());
      }
      // matches/<pair>.jpg for every pair with inliers: the two photos side by side, 320 px each.
      const fs::path drawn = dir / "matches" / (name + ".jpg");
      EXPECT_EQ(fs::exists(drawn), type != "failed" && p["inliers"].get<int>() > 0);
      if (fs::exists(drawn)) {
        const ImageU8 image = ReadImageU8(drawn);
        EXPECT_EQ(image.width, 640);
        EXPECT_EQ(image.height, 240);
      }
    }
    EXPECT_TRUE(solved.count("cam0-cam1") && solved.count("cam1-cam2")) << pairs.dump(1);

    // evaluation.json says what was written and what was left out.
    EXPECT_EQ(outputs["cameras_exported"], json({"cam0", "cam1", "cam2"}));
    ASSERT_EQ(outputs["cameras_omitted"].size(), 1u);
    EXPECT_EQ(outputs["cameras_omitted"][0]["name"], "back");
    EXPECT_EQ(outputs["cameras_omitted"][0]["status"].get<std::string>().rfind("not connected", 0), 0u);
    for (const json& f : outputs["files"]) EXPECT_TRUE(fs::exists(dir / f.get<std::string>())) << f;
    size_t match_images = 0;
    for (const auto& entry : fs::directory_iterator(dir / "matches")) match_images += entry.path().extension() == ".jpg";
    EXPECT_GE(match_images, 2u);
    EXPECT_EQ(outputs["files"].size(), 10u + match_images);  // rig.json, frames.json, pairs.json, the exports, the plot
  }
  EXPECT_TRUE(StagingFolders(out).empty());
}

// Real photos: rig.json with intrinsics only, the images and nothing else. The plot shows the
// estimate alone, in the units of a result without metric scale.
TEST_F(CalibrateIo, PhotosWithoutTruthCalibrateAndPlotTheEstimateAlone) {
  const fs::path photos = dir_ / "photos";
  fs::create_directories(photos);
  fs::copy(dataset() / "images", photos / "images", fs::copy_options::recursive);
  Rig rig = ReadRig(dataset() / "rig.json");
  for (RigCamera& rc : rig.cameras) rc.cam_from_rig.reset();
  WriteRig(rig, photos / "rig.json");
  const fs::path out = dir_ / "out";
  const CliResult r = RunRigsim({"calibrate", photos.string(), "--out", out.string(), "--semantics", "none", "--threads", "2"},
                                dir_ / "run");
  ExpectBackUncalibrated(r);
  const std::string svg = ReadFile(out / "none" / "rig_topdown.svg");
  EXPECT_EQ(svg.find("class=\"truth\""), std::string::npos);
  for (const std::string name : {"cam0", "cam1", "cam2"}) {
    EXPECT_NE(svg.find("class=\"estimate\" data-camera=\"" + name + "\""), std::string::npos) << name << svg;
  }
  EXPECT_NE(svg.find(" units</text>"), std::string::npos);
  EXPECT_TRUE(ReadJson(out / "evaluation.json")["methods"]["none"]["rig"]["summary"]["max_rotation_error_deg"].is_null())
      << "no truth: nothing compared";
}

// Output and errors sent to one log file (`rigsim calibrate ... > log 2>&1`, as a long run is kept)
// stay in the order they were written: the closing error comes after the summary it refers to.
TEST_F(CalibrateIo, OneLogFileKeepsOutputAndErrorsInOrder) {
  const fs::path out = dir_ / "out", log = dir_ / "calibrate.log";
  const std::string command = std::string(RIGSIM_BINARY) + " calibrate '" + dataset().string() + "' --out '" +
                              out.string() + "' --semantics none --threads 2 > '" + log.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 3) << ReadFile(log);
  const std::string text = ReadFile(log);
  const size_t summary = text.find("calibration took");
  const size_t error = text.find("rigsim: not every camera was calibrated (");
  ASSERT_NE(summary, std::string::npos) << text;
  ASSERT_NE(error, std::string::npos) << text;
  EXPECT_LT(summary, error) << text;
  EXPECT_TRUE(error > 0 && text[error - 1] == '\n') << "the error starts a line of its own:\n" << text;
}

// A long calibration says which stage it is in as each begins, on stderr, per semantic mode; the
// tables on stdout stay as they are.
TEST_F(CalibrateIo, ShowsEachStageAsItBegins) {
  const CliResult r = Calibrate({"--semantics", "none,mask"}, dir_ / "out");
  ExpectBackUncalibrated(r);
  const size_t photos = r.err.find("  detecting keypoints in 8 photos\n");
  ASSERT_NE(photos, std::string::npos) << r.err;
  // Each quarter of the photos done, in order (in a log a line each).
  size_t quarter = photos;
  for (const std::string done : {"2", "4", "6"}) {
    const size_t at = r.err.find("  detecting keypoints in 8 photos: " + done + " done", quarter);
    ASSERT_NE(at, std::string::npos) << done << "\n" << r.err;
    quarter = at;
  }
  EXPECT_EQ(r.err.find("8 photos: 8 done"), std::string::npos) << r.err;  // the next stage says it
  for (const std::string mode : {"none", "mask"}) {
    const size_t matching = r.err.find("  " + mode + ": matching the camera pairs");
    const size_t placing = r.err.find("  " + mode + ": placing the rig: rotations, tracks, bundle adjustment");
    ASSERT_NE(matching, std::string::npos) << r.err;
    ASSERT_NE(placing, std::string::npos) << r.err;
    EXPECT_LT(quarter, matching) << r.err;
    EXPECT_LT(matching, placing) << r.err;
  }
  EXPECT_EQ(r.out.find("placing the rig"), std::string::npos) << r.out;
}

// Photos without labels: the default modes (none,mask) fall back to none with a warning saying so;
// a mode that needs labels asked for by name is refused, saying what to do.
TEST_F(CalibrateIo, PhotosWithoutLabelsCalibrateWithoutSemanticsOrSayWhatToDo) {
  const fs::path photos = PhotosWithoutLabels();
  const fs::path out = dir_ / "out";
  const CliResult r = RunRigsim({"calibrate", photos.string(), "--out", out.string(), "--threads", "2"}, dir_ / "default");
  ExpectBackUncalibrated(r);
  EXPECT_NE(r.err.find("warning: " + photos.string() + " has no labels/: calibrating with --semantics none only"),
            std::string::npos)
      << r.err;
  const json methods = ReadJson(out / "evaluation.json")["methods"];
  EXPECT_TRUE(methods.contains("none"));
  EXPECT_FALSE(methods.contains("mask"));

  const fs::path refused = dir_ / "refused";
  const CliResult mask =
      RunRigsim({"calibrate", photos.string(), "--out", refused.string(), "--semantics", "none,mask", "--threads", "2"}, dir_ / "mask");
  EXPECT_EQ(mask.code, 1) << mask.err;
  EXPECT_NE(mask.err.find("rigsim: error: " + (photos / "labels").string() + ": no such folder: --semantics mask needs a label "
                          "image per photo"),
            std::string::npos)
      << mask.err;
  EXPECT_NE(mask.err.find("use --semantics none"), std::string::npos) << mask.err;
  EXPECT_FALSE(fs::exists(refused));
}

// The teaching report plans its calibration as calibrate does: from photos without labels its
// default modes fall back to none with the same warning, and a mode that needs them is refused.
TEST_F(CalibrateIo, ReportOfPhotosWithoutLabelsFallsBackAsCalibrateDoes) {
  const fs::path photos = PhotosWithoutLabels();
  const fs::path out = dir_ / "report";
  const CliResult r = RunRigsim({"report", photos.string(), "--out", out.string(), "--threads", "2"}, dir_ / "default");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + photos.string() + " has no labels/: calibrating with --semantics none only"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("  none: placing the rig"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "index.html"));
  const fs::path refused = dir_ / "refused";
  const CliResult mask =
      RunRigsim({"report", photos.string(), "--out", refused.string(), "--semantics", "mask", "--threads", "2"}, dir_ / "mask");
  EXPECT_EQ(mask.code, 1) << mask.err;
  EXPECT_NE(mask.err.find("--semantics mask needs a label image per photo"), std::string::npos) << mask.err;
  EXPECT_FALSE(fs::exists(refused));
}

TEST_F(CalibrateIo, UserLabelsInIdsAndInColoursGiveIdenticalResults) {
  // Any ids the palette maps back uniquely: the truth with its colour-ambiguous void ids made 0.
  auto ids = [](ImageU8 l, const std::string&, const std::string&) { return LabelsFromColors(ColorizeLabels(l), "x"); };
  const fs::path id_dir = LabelFolder("ids", ids);
  const fs::path color_dir =
      LabelFolder("colors", [&](const ImageU8& l, const std::string& c, const std::string& f) { return ColorizeLabels(ids(l, c, f)); });
  const CliResult a = Calibrate({"--semantics", "mask,gated", "--labels", id_dir.string()}, dir_ / "out_ids");
  const CliResult b = Calibrate({"--semantics", "mask,gated", "--labels", color_dir.string()}, dir_ / "out_colors");
  ExpectBackUncalibrated(a);
  ExpectBackUncalibrated(b);
  const json ea = ReadJson(dir_ / "out_ids" / "evaluation.json"), eb = ReadJson(dir_ / "out_colors" / "evaluation.json");
  EXPECT_EQ(ea["label_source"]["kind"], "folder");
  EXPECT_EQ(ea["label_source"]["folder"], fs::absolute(id_dir).lexically_normal().string());
  EXPECT_EQ(eb["label_source"]["folder"], fs::absolute(color_dir).lexically_normal().string());
  for (const std::string mode : {"mask", "gated"}) {
    SCOPED_TRACE(mode);
    EXPECT_EQ(ReadFile(dir_ / "out_ids" / mode / "rig.json"), ReadFile(dir_ / "out_colors" / mode / "rig.json"));
    const json& pa = ea["methods"][mode]["pairs"];
    const json& pb = eb["methods"][mode]["pairs"];
    ASSERT_EQ(pa.size(), pb.size());
    for (size_t i = 0; i < pa.size(); ++i) {
      EXPECT_EQ(pa[i]["matches"], pb[i]["matches"]);
      EXPECT_EQ(pa[i]["inliers"], pb[i]["inliers"]);
      EXPECT_EQ(pa[i]["rotation_error_deg"], pb[i]["rotation_error_deg"]);
    }
    EXPECT_EQ(ea["methods"][mode]["summary"]["mean_keypoints_per_image"],
              eb["methods"][mode]["summary"]["mean_keypoints_per_image"]);
  }
}

TEST_F(CalibrateIo, NoisyLabelsAreSeededAndRecorded) {
  const std::vector<std::string> noisy = {"--semantics", "mask,gated", "--labels", "noisy", "--label-noise-boundary", "4",
                                          "--label-noise-confusion", "0.3", "--label-noise-seed", "5"};
  const CliResult a = Calibrate(noisy, dir_ / "a");
  std::vector<std::string> one_thread = noisy;
  one_thread.insert(one_thread.end(), {"--threads", "1"});
  const CliResult b = Calibrate(one_thread, dir_ / "b");
  const CliResult truth = Calibrate({"--semantics", "mask,gated"}, dir_ / "truth");
  ExpectBackUncalibrated(a);
  ExpectBackUncalibrated(b);
  ExpectBackUncalibrated(truth);
  const json ea = ReadJson(dir_ / "a" / "evaluation.json"), et = ReadJson(dir_ / "truth" / "evaluation.json");
  EXPECT_EQ(ea["label_source"]["kind"], "noisy");
  EXPECT_EQ(ea["label_source"]["noise"]["boundary_px"], 4);
  EXPECT_EQ(ea["label_source"]["noise"]["confusion_rate"], 0.3);
  EXPECT_EQ(ea["label_source"]["noise"]["seed"], 5);
  EXPECT_EQ(ReadJson(dir_ / "a" / "gated" / "pairs.json")["label_source"]["kind"], "noisy");
  // Same seed, another thread count: the same labels, hence the same estimate.
  for (const std::string mode : {"mask", "gated"}) {
    EXPECT_EQ(ReadFile(dir_ / "a" / mode / "rig.json"), ReadFile(dir_ / "b" / mode / "rig.json")) << mode;
  }
  // The noise reached the features: the mask mode keeps other keypoints than with the truth.
  EXPECT_NE(ea["methods"]["mask"]["summary"]["mean_keypoints_per_image"],
            et["methods"]["mask"]["summary"]["mean_keypoints_per_image"]);
}

TEST_F(CalibrateIo, BadLabelSourcesFailNamingTheFileAndLeaveNothing) {
  // A label image of the wrong size (in an otherwise good folder).
  const fs::path small = LabelFolder("small", [](const ImageU8& l, const std::string& cam, const std::string& frame) {
    return cam == "cam1" && frame == "000001" ? ImageU8(160, 120, 1, 11) : l;
  });
  ExpectCalibrateFails({"--semantics", "mask", "--labels", small.string()}, (small / "cam1" / "000001.png").string(),
                       "label image is 160x120, its image is 320x240");
  // A colour that is no Cityscapes colour.
  const fs::path colours = LabelFolder("colours", [](const ImageU8& l, const std::string& cam, const std::string& frame) {
    ImageU8 c = ColorizeLabels(l);
    if (cam == "cam2" && frame == "000000") c.at(10, 20, 1) ^= 1;
    return c;
  });
  ExpectCalibrateFails({"--semantics", "gated", "--labels", colours.string()}, (colours / "cam2" / "000000.png").string(),
                       "pixel (10, 20) has colour");
  // An id that is no Cityscapes id.
  const fs::path ids = LabelFolder("ids", [](ImageU8 l, const std::string& cam, const std::string& frame) {
    if (cam == "back" && frame == "000000") l.at(0, 0) = 200;
    return l;
  });
  ExpectCalibrateFails({"--semantics", "mask", "--labels", ids.string()}, (ids / "back" / "000000.png").string(),
                       "label id 200, which is no Cityscapes label id");
  // No such folder; noise options without --labels noisy; a bad noise value.
  ExpectCalibrateFails({"--labels", (dir_ / "nowhere").string()}, (dir_ / "nowhere").string(), "no such label folder");
  ExpectCalibrateFails({"--label-noise-boundary", "2"}, "", "--label-noise-boundary needs --labels noisy");
  ExpectCalibrateFails({"--labels", "noisy", "--label-noise-confusion", "1.5"}, "", "--label-noise-confusion");
}

// A mask of the fixture's image size hiding the rows from `hidden_from_row` down (a hood).
ImageU8 HoodMask(int hidden_from_row, int width = 320, int height = 240) {
  ImageU8 m(width, height, 1, 255);
  for (int y = hidden_from_row; y < height; ++y) {
    for (int x = 0; x < width; ++x) m.at(x, y) = 0;
  }
  return m;
}

// --mask hides the lower half of cam0 and cam1 in every mode: what each mask removed is in
// evaluation.json, and it is exactly what the mean number of keypoints per image lost against a
// run without masks; cam2 and back have no mask, which the run says.
TEST_F(CalibrateIo, MasksHideTheirCamerasFeaturesInEveryModeAndAreRecorded) {
  const fs::path masks = dir_ / "masks";
  fs::create_directories(masks);
  WriteImage(masks / "cam0.png", HoodMask(120));
  ImageU8 rgb(320, 240, 3, 200);  // colour works too: black hides
  for (int y = 120; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) rgb.at(x, y, 0) = rgb.at(x, y, 1) = rgb.at(x, y, 2) = 0;
  }
  WriteImage(masks / "cam1.png", rgb);
  const std::vector<std::string> modes = {"--semantics", "none,mask,gated,mask+gated"};
  std::vector<std::string> with = modes;
  with.insert(with.end(), {"--mask", masks.string()});
  const CliResult masked = Calibrate(with, dir_ / "masked");
  const CliResult plain = Calibrate(modes, dir_ / "plain");
  ExpectBackUncalibrated(plain);
  // Half of two 320x240 views hidden leaves too little to place some cameras: written all the same.
  ASSERT_EQ(masked.code, 3) << masked.err;
  EXPECT_NE(masked.err.find("warning: --mask " + masks.string() + " has no mask for cam2, back: their features are not masked"),
            std::string::npos)
      << masked.err;
  const std::string described = "masks: " + masks.string() + " (2 of 4 cameras; cam2, back have none)";
  EXPECT_NE(masked.out.find(described), std::string::npos) << masked.out;
  EXPECT_EQ(plain.out.find("masks:"), std::string::npos) << plain.out;

  const json em = ReadJson(dir_ / "masked" / "evaluation.json"), ep = ReadJson(dir_ / "plain" / "evaluation.json");
  EXPECT_FALSE(ep.contains("masks"));
  const json& mj = em["masks"];
  EXPECT_EQ(mj["folder"], fs::absolute(masks).lexically_normal().string());
  ASSERT_EQ(mj["cameras"].size(), 4u);
  EXPECT_EQ(mj["cameras"][0]["name"], "cam0");
  EXPECT_EQ(mj["cameras"][0]["file"], fs::absolute(masks / "cam0.png").lexically_normal().string());
  EXPECT_DOUBLE_EQ(mj["cameras"][0]["hidden_percent"].get<double>(), 50.0);
  EXPECT_TRUE(mj["cameras"][2]["file"].is_null());
  EXPECT_TRUE(mj["cameras"][3]["features_removed"]["none"].is_null());
  for (const std::string mode : {"none", "mask", "gated", "mask+gated"}) {
    SCOPED_TRACE(mode);
    int removed = 0;
    for (int c = 0; c < 2; ++c) {
      const int n = mj["cameras"][c]["features_removed"][mode].get<int>();
      EXPECT_GT(n, 20) << "camera " << c;
      removed += n;
    }
    // 4 cameras x 2 frames; with every keypoint kept (far below --max-features), the masked run
    // keeps the plain run's keypoints less those the masks removed.
    const double mean_masked = em["methods"][mode]["summary"]["mean_keypoints_per_image"].get<double>();
    const double mean_plain = ep["methods"][mode]["summary"]["mean_keypoints_per_image"].get<double>();
    EXPECT_NEAR(mean_masked * 8 + removed, mean_plain * 8, 1e-6);
    EXPECT_EQ(ReadJson(dir_ / "masked" / mode / "pairs.json")["masks"], mj["folder"]);
  }
  // Another thread count: the same estimate.
  with.insert(with.end(), {"--threads", "1"});
  const CliResult one_thread = Calibrate(with, dir_ / "one_thread");
  ASSERT_EQ(one_thread.code, 3) << one_thread.err;
  for (const std::string mode : {"none", "mask+gated"}) {
    EXPECT_EQ(ReadFile(dir_ / "masked" / mode / "rig.json"), ReadFile(dir_ / "one_thread" / mode / "rig.json")) << mode;
  }
  EXPECT_EQ(ReadJson(dir_ / "one_thread" / "evaluation.json")["masks"], mj);
}

TEST_F(CalibrateIo, BadMasksFailNamingTheFileAndLeaveNothing) {
  ExpectCalibrateFails({"--mask", (dir_ / "nowhere").string()}, "--mask " + (dir_ / "nowhere").string(), "no such folder");
  int n = 0;
  // A folder with cam0's good mask and `bad`.
  const auto folder = [&](const std::function<void(const fs::path&)>& bad) {
    const fs::path dir = dir_ / ("masks" + std::to_string(n++));
    fs::create_directories(dir);
    WriteImage(dir / "cam0.png", HoodMask(120));
    bad(dir);
    return dir;
  };
  fs::path d = folder([](const fs::path& dir) { WriteImage(dir / "cam3.png", HoodMask(120)); });
  ExpectCalibrateFails({"--mask", d.string()}, (d / "cam3.png").string(),
                       "no camera 'cam3' in " + (dataset() / "rig.json").string() + " (did you mean 'cam0'?); its cameras are "
                       "cam0, cam1, cam2, back");
  d = folder([](const fs::path& dir) { WriteImage(dir / "cam1.png", HoodMask(100, 320, 200)); });
  ExpectCalibrateFails({"--mask", d.string()}, (d / "cam1.png").string(),
                       "the mask is 320x200 but camera cam1's images are 320x240");
  d = folder([](const fs::path& dir) { WriteFile(dir / "cam2.png", "no image"); });
  ExpectCalibrateFails({"--mask", d.string()}, (d / "cam2.png").string(), "");
  d = folder([](const fs::path& dir) { WriteImage(dir / "back.png", HoodMask(0)); });
  ExpectCalibrateFails({"--mask", d.string()}, (d / "back.png").string(), "the mask is black everywhere");
}

TEST_F(CalibrateIo, LibraryNamesABadUserLabelImage) {
  const fs::path small = LabelFolder("small", [](const ImageU8& l, const std::string& cam, const std::string&) {
    return cam == "cam0" ? ImageU8(320, 200, 1, 11) : l;
  });
  CalibrationRunOptions options;
  options.labels = LabelSource::Folder(small);
  EXPECT_THAT([&] { CalibrateDataset(dataset(), options, {SemanticMode::kMask}); },
              ThrowsNaming<std::runtime_error>(small / "cam0", "label image is 320x200, its image is 320x240"));
}

}  // namespace
}  // namespace rigsim
