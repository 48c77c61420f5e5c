// Cameras on a moving rig: the capture time of every row (rolling shutter), the spread of the
// colour samples over the exposure (motion blur), a time offset, and the ground truth that goes
// with them (poses.json, correspondence maps).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "dataset/ground_truth.h"
#include "dataset/image_io.h"
#include "renderer/render_dataset.h"
#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"
#include "dataset/capture_poses.h"
#include "rigs/trajectories.h"
#include "scene/scene_pose.h"
#include "scene/test_scenes.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

constexpr uint16_t kNearId = 1, kWallId = 2;

// A near quad covering x < 0 at depth 10 before a wall at depth 20 (the camera frame of an
// identity pose): a vertical edge at x = 0.
Scene EdgeScene() {
  Scene scene;
  const int grey = AddMaterial(scene, Eigen::Vector4f(0.8f, 0.8f, 0.8f, 1));
  const int dark = AddMaterial(scene, Eigen::Vector4f(0.1f, 0.1f, 0.1f, 1));
  AddFrontQuad(scene, -30, 0, -30, 30, 10, kCar, kNearId, grey);
  AddFrontQuad(scene, -60, 60, -60, 60, 20, kRoad, kWallId, dark);
  return scene;
}

// Frames of a rig moving along its x axis at `speed` m/s from the origin (rig = world axes).
FramesFile SlidingFrames(double speed) {
  FramesFile frames;
  frames.frames.push_back({"000000", Rigid3d(), 0.0});
  frames.frames.push_back({"000001", Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-speed, 0, 0)), 1.0});
  return frames;
}

// Column where the near quad ends in row y (first pixel showing the wall).
int EdgeColumn(const ImageU16& instance, int y) {
  for (int x = 0; x < instance.width; ++x) {
    if (instance.at(x, y) == kWallId) return x;
  }
  return instance.width;
}

// Least-squares slope of the edge column over the rows.
double EdgeSlope(const ImageU16& instance) {
  double sy = 0, sx = 0, syy = 0, sxy = 0;
  const int n = instance.height;
  for (int y = 0; y < n; ++y) {
    const double x = EdgeColumn(instance, y);
    sy += y, sx += x, syy += double(y) * y, sxy += double(y) * x;
  }
  return (n * sxy - sy * sx) / (n * syy - sy * sy);
}

RigCamera MovingCamera(double readout_s, bool bottom_to_top = false, double exposure_s = 0.0) {
  RigCamera cam{"cam", Camera(CameraModelId::kPinhole, 160, 120, {100, 100, 79.5, 59.5}), Rigid3d(), 0.0};
  cam.readout_s = readout_s;
  cam.readout_bottom_to_top = bottom_to_top;
  cam.exposure_s = exposure_s;
  return cam;
}

TEST(MovingRenderTest, RollingShutterSlantsAVerticalEdgeByTheAnalyticAmount) {
  const Scene scene = EdgeScene();
  Renderer renderer(scene);
  const double speed = 20.0, readout = 0.05;  // 1 m of travel during the readout
  const RigTrajectory trajectory(SlidingFrames(speed));
  for (const bool bottom_to_top : {false, true}) {
    const RigCamera cam = MovingCamera(readout, bottom_to_top);
    MovingCameraView view{&cam, 0.0, [&](double t) { return trajectory.RigFromWorldAt(t); }};
    const RenderedView rendered = renderer.Render(view, RenderOptions());
    // Row r is seen from x = speed * t_r: the edge at x = 0, depth 10 appears at
    // cx - fx * speed * t_r / 10, t_r = r * readout / height (top to bottom).
    const double per_row = -100.0 * speed * (readout / 120) / 10.0;  // -0.833 px per row
    EXPECT_NEAR(EdgeSlope(rendered.instance), bottom_to_top ? -per_row : per_row, 0.01) << bottom_to_top;
    const int first_row = bottom_to_top ? 119 : 0;
    EXPECT_NEAR(EdgeColumn(rendered.instance, first_row), 79.5, 1.0);  // the first row read out: from x = 0
    // Depth at the pixel centre's time: the near quad is 10 m away in every row.
    EXPECT_NEAR(rendered.range.at(10, 60), 10.0 / cam.camera.CamFromImg({10, 60})->normalized().z(), 1e-3);
  }
  // A global shutter on the same rig: a straight edge.
  const RigCamera still = MovingCamera(0.0);
  MovingCameraView view{&still, 0.0, [&](double t) { return trajectory.RigFromWorldAt(t); }};
  EXPECT_NEAR(EdgeSlope(renderer.Render(view, RenderOptions()).instance), 0.0, 1e-9);
}

TEST(MovingRenderTest, ExposureBlursTheColourNotTheGroundTruth) {
  const Scene scene = EdgeScene();
  Renderer renderer(scene);
  const RigTrajectory trajectory(SlidingFrames(20.0));
  RenderOptions options;
  options.samples_per_pixel = 16;
  const RigCamera sharp = MovingCamera(0.0), blurred = MovingCamera(0.0, false, 0.02);  // 0.4 m: 4 px of blur
  auto render = [&](const RigCamera& cam) {
    return renderer.Render(MovingCameraView{&cam, 0.0, [&](double t) { return trajectory.RigFromWorldAt(t); }}, options);
  };
  const RenderedView a = render(sharp), b = render(blurred);
  EXPECT_EQ(a.label.data, b.label.data);  // ground truth at mid exposure: where the sharp view is
  EXPECT_EQ(a.range.data, b.range.data);
  // Grey levels strictly between the near quad's and the wall's: 1 column sharp, about 4 blurred.
  auto mixed_columns = [](const RenderedView& v) {
    const int lo = v.rgb.at(150, 60, 0), hi = v.rgb.at(5, 60, 0);
    int n = 0;
    for (int x = 0; x < v.rgb.width; ++x) n += v.rgb.at(x, 60, 0) > lo + 3 && v.rgb.at(x, 60, 0) < hi - 3;
    return n;
  };
  EXPECT_LE(mixed_columns(a), 1);
  EXPECT_GE(mixed_columns(b), 3);
  EXPECT_LE(mixed_columns(b), 5);
}

// A rig turning and moving through the animated box scene, 0.1 s between frames.
FramesFile TurningFrames() {
  FramesFile frames;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.05 * k, Eigen::Vector3d::UnitY()));
    const Eigen::Vector3d centre(0.3 * k, 0.0, 0.2 * k);
    frames.frames.push_back({"00000" + std::to_string(k), Rigid3d(turn, centre).Inverse(), 0.1 * k});
  }
  return frames;
}

TEST(MovingRenderTest, ATimeOffsetRendersWhatASynchronisedCameraAtTheInterpolatedPoseRenders) {
  Scene scene = AnimatedBoxScene();
  AddFrontQuad(scene, -20, 20, -20, 20, 15, kRoad, 9);
  RenderJob job;
  job.scene = &scene;
  const Rigid3d cam_from_rig(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY())), Eigen::Vector3d(0.1, 0, 0));
  job.rig.cameras.push_back({"late", Camera(CameraModelId::kPinhole, 96, 64, {60, 60, 47.5, 31.5}), cam_from_rig, 0.037});
  job.frames = TurningFrames();
  job.options.samples_per_pixel = 4;
  const TempDir dir;
  RenderDataset(job, dir, true);
  const DatasetLayout layout(dir);

  Renderer renderer(scene);
  const RigTrajectory trajectory(job.frames);
  for (const Frame& frame : job.frames.frames) {
    const double t = frame.timestamp_s + 0.037;
    const std::vector<SceneMesh> posed = PoseMeshesAt(scene, t);
    renderer.SetMeshes(posed);
    const Rigid3d cam_from_world = cam_from_rig * trajectory.RigFromWorldAt(t);
    const RenderedView expected = renderer.Render(job.rig.cameras[0].camera, cam_from_world, job.options);
    EXPECT_EQ(ReadImageU8(layout.Image("late", frame.name)).data, expected.rgb.data) << frame.name;
    EXPECT_EQ(ReadImageU16(layout.Instance("late", frame.name)).data, expected.instance.data) << frame.name;
    EXPECT_EQ(ReadImageF(layout.Depth("late", frame.name)).data, expected.range.data) << frame.name;
    // The rig has moved from the frame's pose (3 m/s): the view differs from the frame's own.
    const RenderedView at_frame = renderer.Render(job.rig.cameras[0].camera, cam_from_rig * *frame.rig_from_world, job.options);
    EXPECT_NE(at_frame.range.data, expected.range.data);
  }
  // poses.json records the pose the camera was rendered from.
  const nlohmann::json poses = nlohmann::json::parse(ReadFile(layout.PosesJson()));
  const nlohmann::json& f1 = poses["cameras"][0]["frames"][1];
  EXPECT_DOUBLE_EQ(f1["capture_time_s"].get<double>(), 0.137);
  const Rigid3d recorded(Eigen::Quaterniond(f1["cam_from_world"]["rotation_wxyz"][0], f1["cam_from_world"]["rotation_wxyz"][1],
                                            f1["cam_from_world"]["rotation_wxyz"][2], f1["cam_from_world"]["rotation_wxyz"][3]),
                         Eigen::Vector3d(f1["cam_from_world"]["translation"][0], f1["cam_from_world"]["translation"][1],
                                         f1["cam_from_world"]["translation"][2]));
  const Rigid3d truth = cam_from_rig * trajectory.RigFromWorldAt(0.137);
  EXPECT_LT((recorded.translation - truth.translation).norm(), 1e-12);
  EXPECT_LT(RotationDifferenceDeg(recorded.rotation, truth.rotation), 1e-9);
}

TEST(MovingRenderTest, AMovingObjectUnderARollingShutterSlantsByItsOwnSpeed) {
  // The box moves at 2 m/s along x at depth 6 (its front face at 5.5); the rig stands still.
  const Scene scene = AnimatedBoxScene();
  RenderJob job;
  job.scene = &scene;
  RigCamera cam{"rs", Camera(CameraModelId::kPinhole, 160, 120, {100, 100, 79.5, 59.5}), Rigid3d(), 0.0};
  cam.readout_s = 0.9;  // the box moves 1.8 m during the readout
  job.rig.cameras.push_back(cam);
  job.frames.frames = {{"000000", Rigid3d(), 0.0}, {"000001", Rigid3d(), 0.5}};
  const TempDir dir;
  RenderDataset(job, dir, true);
  const ImageU16 instance = ReadImageU16(DatasetLayout(dir).Instance("rs", "000000"));
  // The box's left edge (x = centre - 0.5 at depth 5.5) in rows of its image (rows 51 to 68).
  auto left_edge = [&](int y) {
    for (int x = 0; x < instance.width; ++x) {
      if (instance.at(x, y) == 5) return x;
    }
    return -1;
  };
  auto expected = [&](int y) {
    const double t = y * 0.9 / 120;
    return 79.5 + 100.0 * (-1 + 2 * t - 0.5) / 5.5;
  };
  for (int y : {52, 59, 66}) EXPECT_NEAR(left_edge(y), expected(y), 1.0) << y;
  EXPECT_NEAR(left_edge(66) - left_edge(52), expected(66) - expected(52), 1.0);  // 4.1 px
}

// Lifts every pixel of A by its depth, projects it into B, and compares with the map.
void ExpectMapMatchesLiftAndProject(const ImageF& map, const Camera& cam_a, const ImageF& depth_a, const ViewPose& pose_a,
                                    const Camera& cam_b, const ViewPose& pose_b, int* visible) {
  *visible = 0;
  double worst = 0;
  for (int y = 0; y < depth_a.height; ++y) {
    for (int x = 0; x < depth_a.width; ++x) {
      if (!(depth_a.at(x, y) > 0)) {
        EXPECT_EQ(map.at(x, y, 2), 0.0f);
        continue;
      }
      const Eigen::Vector3d x_world = pose_a.Row(y).Inverse() * (cam_a.CamFromImg({x, y})->normalized() * depth_a.at(x, y));
      const auto in_b = ProjectIntoView(x_world, cam_b, pose_b, y);
      if (!in_b) continue;
      if (map.at(x, y, 2) == 1.0f) ++*visible;
      // With a rolling shutter: the row B sees the point in is the row whose pose projects it there,
      // or, where the point crosses a row boundary as the rows' poses change, its neighbour.
      if (pose_b.Rolling() && map.at(x, y, 2) == 1.0f) {
        const long row = std::lround(in_b->px.y());
        const auto again = cam_b.ImgFromCam(pose_b.Row(int(row)) * x_world);
        ASSERT_TRUE(again.has_value());
        EXPECT_LE(std::abs(std::lround(again->y()) - row), 1) << "row " << row;
        double one_row = 0.0;  // how far the point moves in the image from this row's pose to a neighbour's
        for (long r : {row - 1, row + 1}) {
          if (r < 0 || r >= cam_b.height()) continue;
          if (auto px = cam_b.ImgFromCam(pose_b.Row(int(r)) * x_world)) one_row = std::max(one_row, (*px - *again).norm());
        }
        EXPECT_LE((*again - in_b->px).norm(), one_row + 1e-9) << "row " << row;
      }
      worst = std::max(worst, (in_b->px - Eigen::Vector2d(map.at(x, y, 0), map.at(x, y, 1))).norm());
    }
  }
  EXPECT_LE(worst, 0.01);
}

TEST(MovingRenderTest, CorrespondenceMapsAgreeWithLiftAndProjectAndWithTheOverlap) {
  Scene scene;
  AddFrontQuad(scene, -20, 20, -20, 20, 12, kRoad, 1);
  AddFrontQuad(scene, -1.5, 0.5, -1, 1, 6, kCar, 2);
  AddQuad(scene, {-20, 3, 4}, {20, 3, 4}, {20, 3, 30}, {-20, 3, 30}, kRoad, 3);
  for (const double readout : {0.0, 0.03}) {
    RenderJob job;
    job.scene = &scene;
    const Camera camera(CameraModelId::kOpenCV, 96, 64, {60, 60, 47.5, 31.5, -0.1, 0.01, 0, 0});
    RigCamera a{"a", camera, Rigid3d(), 0.0};
    RigCamera b{"b", camera, Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(-0.4, 0, 0)), 0.0};
    a.readout_s = b.readout_s = readout;
    job.rig.cameras = {a, b};
    job.frames = SlidingFrames(10.0);
    job.frames.frames[1].timestamp_s = 0.1;
    job.extras.correspondence = true;
    const TempDir tmp;
    const std::filesystem::path dir = tmp / ("readout" + std::to_string(readout));
    RenderDataset(job, dir, true);
    const DatasetLayout layout(dir);
    const RigTrajectory trajectory(job.frames);
    auto pose_of = [&](const RigCamera& cam, double t0) {
      ViewPose pose;
      for (int y = 0; y < (readout > 0 ? 64 : 1); ++y) pose.cam_from_world_rows.push_back(*cam.cam_from_rig * trajectory.RigFromWorldAt(t0 + cam.RowTime(y)));
      return pose;
    };
    const ImageF depth_a = ReadImageF(layout.Depth("a", "000000"));
    int surface = 0;
    for (float r : depth_a.data) surface += r > 0;
    // Camera a in camera b, frame 0: the map, and its visible share is the overlap figure.
    int visible = 0;
    ExpectMapMatchesLiftAndProject(ReadImageFChannels(layout.Correspondence("a", "b", "000000")), camera, depth_a,
                                   pose_of(a, 0.0), camera, pose_of(b, 0.0), &visible);
    const nlohmann::json overlap = nlohmann::json::parse(ReadFile(layout.OverlapJson()));
    const ImageF ab1 = ReadImageFChannels(layout.Correspondence("a", "b", "000001"));
    int visible1 = 0, surface1 = 0;
    for (int i = 0; i < 96 * 64; ++i) visible1 += ab1.data[3 * i + 2] == 1.0f;
    for (float r : ReadImageF(layout.Depth("a", "000001")).data) surface1 += r > 0;
    EXPECT_GT(visible, 500) << readout;
    EXPECT_NEAR(overlap["pairs"][0]["overlap_a_in_b"].get<double>(), (double(visible) / surface + double(visible1) / surface1) / 2, 1e-12);
    // Optical flow of camera a from frame 0 to frame 1.
    ExpectMapMatchesLiftAndProject(ReadImageFChannels(layout.Flow("a", "000000")), camera, depth_a, pose_of(a, 0.0), camera,
                                   pose_of(a, 0.1), &visible);
    EXPECT_GT(visible, 2000) << readout;
    EXPECT_FALSE(std::filesystem::exists(layout.Flow("a", "000001")));  // no next frame
  }
}

TEST(MovingRenderTest, NormalsAreInTheCameraFrameFacingTheCamera) {
  Scene scene;
  AddFrontQuad(scene, -20, 20, -20, 20, 12, kRoad, 1);
  Renderer renderer(scene);
  RenderOptions options;
  options.normals = true;
  // Turned 0.3 rad about y: the wall's normal (0, 0, -1) in the world is turned in the camera frame.
  const Rigid3d cam_from_world(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d::Zero());
  const RenderedView view = renderer.Render(SmallPinhole(), cam_from_world, options);
  const Eigen::Vector3d expected = cam_from_world.rotation * Eigen::Vector3d(0, 0, -1);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(view.normal.at(32, 24, c), expected[c], 1e-6);
  EXPECT_TRUE(renderer.Render(SmallPinhole(), cam_from_world, RenderOptions()).normal.empty());
}

}  // namespace
}  // namespace rigsim
