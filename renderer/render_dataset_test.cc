#include "renderer/render_dataset.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "dataset/render_shards.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

// Entries of the folder (to check that nothing, not even a staging folder, was left).
int NumEntries(const fs::path& dir) { return int(std::distance(fs::directory_iterator(dir), fs::directory_iterator())); }

void AddQuad(Scene& scene, const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
             const Eigen::Vector3f& p3, uint8_t class_id, uint16_t instance_id) {
  SceneMesh mesh;
  mesh.name = "quad" + std::to_string(scene.meshes.size());
  mesh.class_id = class_id;
  mesh.instance_id = instance_id;
  mesh.positions = {p0, p1, p2, p3};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  scene.meshes.push_back(mesh);
}

// A wall 5 m ahead (rig frame = world frame at frame 0) and a box-like quad in front of it.
Scene WallScene() {
  Scene scene;
  scene.source = "wall";
  AddQuad(scene, {-20, -20, 5}, {20, -20, 5}, {20, 20, 5}, {-20, 20, 5}, 11 /*building*/, 1);
  AddQuad(scene, {-0.5f, -0.5f, 3}, {0.5f, -0.5f, 3}, {0.5f, 0.5f, 3}, {-0.5f, 0.5f, 3}, 26 /*car*/, 2);
  return scene;
}

// cam0 at the rig origin looking along +z, cam1 0.3 m to the right turned 20 degrees,
// cam2 looking backwards (sees only sky).
RenderJob WallJob(const Scene& scene) {
  RenderJob job;
  job.scene = &scene;
  job.scene_name = "wall.glb";
  const Camera camera(CameraModelId::kOpenCV, 40, 30, {30, 30, 19.5, 14.5, -0.05, 0, 0, 0});
  const Rigid3d cam1_from_rig =
      Rigid3d(Eigen::AngleAxisd(DegToRad(20), Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d::Zero()) *
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.3, 0, 0));
  const Rigid3d cam2_from_rig(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d::Zero());
  job.rig.cameras = {RigCamera{"cam0", camera, Rigid3d(), 0.0}, RigCamera{"cam1", camera, cam1_from_rig, 0.0},
                     RigCamera{"cam2", camera, cam2_from_rig, 0.0}};
  for (int f = 0; f < 2; ++f) {
    Frame frame;
    frame.name = "00000" + std::to_string(f);
    frame.rig_from_world = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.2 * f, 0, 0));
    frame.timestamp_s = 0.1 * f;
    job.frames.frames.push_back(frame);
  }
  job.options.samples_per_pixel = 1;
  job.options.seed = 42;
  return job;
}

TEST(RenderDatasetTest, WritesTheWholeLayout) {
  const TempDir scratch;
  const Scene scene = WallScene();
  const RenderJob job = WallJob(scene);
  const fs::path out = scratch / "dataset";
  std::vector<std::pair<int, int>> calls;
  RenderDataset(job, out, false, [&](int done, int total) { calls.emplace_back(done, total); });

  ASSERT_EQ(calls.size(), 6u);
  EXPECT_EQ(calls.back(), std::make_pair(6, 6));
  EXPECT_EQ(NumEntries(scratch), 1);  // the dataset, no staging leftovers

  const DatasetLayout layout(out);
  EXPECT_TRUE(fs::exists(layout.RigJson()));
  EXPECT_TRUE(fs::exists(layout.FramesJson()));
  EXPECT_TRUE(fs::exists(layout.OverlapJson()));
  const Renderer renderer(scene);
  for (const RigCamera& cam : job.rig.cameras) {
    for (const Frame& frame : job.frames.frames) {
      for (const fs::path& p : {layout.Image(cam.name, frame.name), layout.Label(cam.name, frame.name),
                                layout.LabelColor(cam.name, frame.name), layout.Instance(cam.name, frame.name),
                                layout.Depth(cam.name, frame.name)}) {
        EXPECT_TRUE(fs::is_regular_file(p)) << p;
      }
      // What is on disk is what the renderer produces for that pose.
      const RenderedView view =
          renderer.Render(cam.camera, *cam.cam_from_rig * *frame.rig_from_world, job.options);
      EXPECT_EQ(ReadImageU8(layout.Image(cam.name, frame.name), 3).data, view.rgb.data);
      EXPECT_EQ(ReadImageU8(layout.Label(cam.name, frame.name), 1).data, view.label.data);
      EXPECT_EQ(ReadImageU8(layout.LabelColor(cam.name, frame.name), 3).data, ColorizeLabels(view.label).data);
      EXPECT_EQ(ReadImageU16(layout.Instance(cam.name, frame.name)).data, view.instance.data);
      EXPECT_EQ(ReadImageF(layout.Depth(cam.name, frame.name)).data, view.range.data);
    }
  }

  const Rig rig = ReadRig(layout.RigJson());
  ASSERT_EQ(rig.cameras.size(), 3u);
  EXPECT_EQ(rig.cameras[1].name, "cam1");
  ASSERT_TRUE(rig.cameras[1].cam_from_rig.has_value());
  EXPECT_LT((rig.cameras[1].cam_from_rig->translation - job.rig.cameras[1].cam_from_rig->translation).norm(), 1e-9);

  const FramesFile frames = ReadFrames(layout.FramesJson());
  ASSERT_EQ(frames.frames.size(), 2u);
  EXPECT_EQ(frames.scene, "wall.glb");
  EXPECT_EQ(frames.seed, 42u);
  EXPECT_EQ(frames.frames[1].name, "000001");

  std::ifstream overlap_file(layout.OverlapJson());
  const nlohmann::json overlap = nlohmann::json::parse(overlap_file);
  EXPECT_EQ(overlap.at("frames").get<int>(), 2);
  const auto& pairs = overlap.at("pairs");
  ASSERT_EQ(pairs.size(), 3u);  // (cam0, cam1), (cam0, cam2), (cam1, cam2)
  EXPECT_EQ(pairs[0].at("a"), "cam0");
  EXPECT_EQ(pairs[0].at("b"), "cam1");
  const double a_in_b = pairs[0].at("overlap_a_in_b").get<double>();
  const double b_in_a = pairs[0].at("overlap_b_in_a").get<double>();
  EXPECT_GT(a_in_b, 0.2);
  EXPECT_LT(a_in_b, 0.95);
  EXPECT_GT(b_in_a, 0.2);
  EXPECT_LT(b_in_a, 0.95);
  // cam2 looks away from everything: no surface, no overlap either way.
  EXPECT_EQ(pairs[1].at("b"), "cam2");
  EXPECT_EQ(pairs[1].at("overlap_a_in_b").get<double>(), 0.0);
  EXPECT_EQ(pairs[1].at("overlap_b_in_a").get<double>(), 0.0);
}

// Every file of a dataset but rig.json, by its path inside the dataset, with its bytes.
std::map<std::string, std::string> FilesBesideRigJson(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().filename() == "rig.json") continue;
    std::ifstream in(e.path(), std::ios::binary);
    files[fs::relative(e.path(), dir).string()] = std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

TEST(RenderDatasetTest, ACameraWithARenderLensIsRenderedThroughItAndKeepsItsModel) {
  const TempDir scratch;
  // A pinhole model, and the lens it models: barrel-distorted, as a real lens is.
  const Camera model(CameraModelId::kPinhole, 80, 60, {40, 40, 39.5, 29.5});
  const Camera lens(CameraModelId::kFullOpenCV, 80, 60, {40, 40, 39.5, 29.5, -0.2, 0.02, 0, 0, 0.01, 0, 0, 0});
  // A small plate 3 m away where the lens images pixel (10, 8), near the corner, on a wall.
  const Eigen::Vector3d ray = *lens.CamFromImg(Eigen::Vector2d(10, 8));
  const Eigen::Vector3d point = ray / ray.z() * 3.0;
  const Eigen::Vector2d by_lens = *lens.ImgFromCam(point), by_model = *model.ImgFromCam(point);
  ASSERT_GT((by_lens - by_model).norm(), 5.0);  // the two put it pixels apart
  Scene scene;
  scene.source = "plate";
  AddQuad(scene, {-20, -20, 5}, {20, -20, 5}, {20, 20, 5}, {-20, 20, 5}, 11 /*building*/, 1);
  const Eigen::Vector3f c = point.cast<float>();
  const float h = 0.06f;
  AddQuad(scene, c + Eigen::Vector3f(-h, -h, 0), c + Eigen::Vector3f(h, -h, 0), c + Eigen::Vector3f(h, h, 0),
          c + Eigen::Vector3f(-h, h, 0), 26 /*car*/, 2);
  RenderJob job;
  job.scene = &scene;
  job.scene_name = "plate.glb";
  job.rig.cameras = {RigCamera{"cam0", model, Rigid3d(), 0.0}};
  job.rig.cameras[0].render_lens = lens;
  Frame frame;
  frame.name = "000000";
  frame.rig_from_world = Rigid3d();
  job.frames.frames.push_back(frame);
  job.options.samples_per_pixel = 1;
  RenderDataset(job, scratch / "lens", false);

  // The plate is where the lens puts it, with its true range; where the model puts it is the wall.
  const DatasetLayout layout(scratch / "lens");
  const ImageU16 instance = ReadImageU16(layout.Instance("cam0", "000000"));
  const ImageF range = ReadImageF(layout.Depth("cam0", "000000"));
  const int lx = int(std::lround(by_lens.x())), ly = int(std::lround(by_lens.y()));
  EXPECT_EQ(instance.at(lx, ly), 2);
  EXPECT_NEAR(range.at(lx, ly), point.norm(), 0.05);
  EXPECT_EQ(instance.at(int(std::lround(by_model.x())), int(std::lround(by_model.y()))), 1);
  // rig.json keeps the model, the one the calibrator is given, with the lens beside it.
  const Rig written = ReadRig(layout.RigJson());
  EXPECT_EQ(written.cameras[0].camera.params(), model.params());
  ASSERT_TRUE(written.cameras[0].render_lens.has_value());
  EXPECT_EQ(written.cameras[0].render_lens->params(), lens.params());
  // Every other file, ground truth and overlap included, is the render of a camera that is the lens.
  RenderJob through_lens = job;
  through_lens.rig = job.rig.AsRendered();
  RenderDataset(through_lens, scratch / "plain", false);
  EXPECT_EQ(FilesBesideRigJson(scratch / "lens"), FilesBesideRigJson(scratch / "plain"));
  EXPECT_EQ(ReadRig(scratch / "plain" / "rig.json").cameras[0].camera.params(), lens.params());
}

TEST(RenderDatasetTest, IncompleteJobWritesNothing) {
  const TempDir scratch;
  const Scene scene = WallScene();
  const fs::path out = scratch / "dataset";

  RenderJob job = WallJob(scene);
  job.rig.cameras[1].cam_from_rig.reset();
  EXPECT_THROW(RenderDataset(job, out, false), std::invalid_argument);
  EXPECT_EQ(NumEntries(scratch), 0);

  job = WallJob(scene);
  job.frames.frames[0].rig_from_world.reset();
  EXPECT_THROW(RenderDataset(job, out, false), std::invalid_argument);
  job = WallJob(scene);
  job.rig.cameras[2].name = "cam0";
  EXPECT_THROW(RenderDataset(job, out, false), std::invalid_argument);
  job = WallJob(scene);
  job.rig.cameras[0].name = "../escape";
  EXPECT_THROW(RenderDataset(job, out, false), std::invalid_argument);
  EXPECT_EQ(NumEntries(scratch), 0);
}

TEST(RenderDatasetTest, FailureMidwayLeavesNothing) {
  const TempDir scratch;
  const Scene scene = WallScene();
  const RenderJob job = WallJob(scene);
  const fs::path out = scratch / "dataset";
  // The callback runs after views have been written to the staging folder.
  auto interrupt = [](int done, int) {
    if (done == 3) throw std::runtime_error("interrupted");
  };
  EXPECT_THROW(RenderDataset(job, out, false, interrupt), std::runtime_error);
  EXPECT_EQ(NumEntries(scratch), 0);
}

TEST(RenderDatasetTest, UnwritablePlaceThrowsAndWritesNothing) {
  // A regular file where a parent folder should be: no folder can be made there (even as root,
  // where permission bits would not stop us).
  const TempDir scratch;
  const Scene scene = WallScene();
  const fs::path blocker = scratch / "not_a_folder";
  std::ofstream(blocker) << "x";
  EXPECT_ANY_THROW(RenderDataset(WallJob(scene), blocker / "dataset", false));
  EXPECT_EQ(NumEntries(scratch), 1);
  EXPECT_TRUE(fs::is_regular_file(blocker));
}

TEST(RenderDatasetTest, ExistingOutputNeedsForceAndSurvivesAFailure) {
  const TempDir scratch;
  const Scene scene = WallScene();
  RenderJob job = WallJob(scene);
  job.frames.frames.resize(1);
  const fs::path out = scratch / "dataset";
  fs::create_directories(out);
  std::ofstream(out / "keep.txt") << "previous";
  // A folder of other files is never replaced, --force or not (dataset/output_folder.h).
  EXPECT_THROW(RenderDataset(job, out, true), std::runtime_error);
  EXPECT_TRUE(fs::exists(out / "keep.txt"));
  fs::remove(out / "keep.txt");

  RenderDataset(job, out, false);
  const fs::path previous = DatasetLayout(out).Depth("cam2", "000000");
  EXPECT_THROW(RenderDataset(job, out, false), std::runtime_error);
  EXPECT_TRUE(fs::exists(previous));

  auto interrupt = [](int done, int) {
    if (done == 2) throw std::runtime_error("interrupted");
  };
  job.frames.frames[0].name = "000001";
  EXPECT_THROW(RenderDataset(job, out, true, interrupt), std::runtime_error);
  EXPECT_TRUE(fs::exists(previous));  // the previous output is intact
  EXPECT_EQ(NumEntries(scratch), 1);

  RenderDataset(job, out, true);
  EXPECT_FALSE(fs::exists(previous));
  EXPECT_TRUE(fs::exists(DatasetLayout(out).Depth("cam2", "000001")));
  EXPECT_EQ(NumEntries(scratch), 1);
}

// Photometric variation: off (zero magnitudes, whatever its seed) writes exactly the dataset of a
// job without it; on, only the RGB images change, the same seed gives the same bytes whatever the
// thread count, and photometric.json records what each camera drew.
TEST(RenderDatasetTest, PhotometricVariationChangesOnlyRgbAndIsRecorded) {
  const TempDir scratch;
  const Scene scene = WallScene();
  RenderJob plain = WallJob(scene);
  RenderJob off = plain;
  off.photometric.seed = 99;  // a seed alone enables nothing
  RenderJob on = plain;
  on.photometric = PhotometricOptions::Defaults();
  on.photometric.read_noise_stddev = 0.01;
  on.photometric.seed = 7;
  RenderJob on_one_thread = on;
  on_one_thread.options.num_threads = 1;
  on.options.num_threads = 2;
  const fs::path a = scratch / "plain", b = scratch / "off", c = scratch / "on", d = scratch / "on1";
  RenderDataset(plain, a, false);
  RenderDataset(off, b, false);
  RenderDataset(on, c, false);
  RenderDataset(on_one_thread, d, false);
  const DatasetLayout la(a), lb(b), lc(c), ld(d);
  EXPECT_FALSE(fs::exists(la.PhotometricJson()));
  EXPECT_FALSE(fs::exists(lb.PhotometricJson()));
  ASSERT_TRUE(fs::exists(lc.PhotometricJson()));
  int changed = 0;
  for (const RigCamera& cam : plain.rig.cameras) {
    for (const Frame& frame : plain.frames.frames) {
      const std::string& n = cam.name;
      const std::string& f = frame.name;
      EXPECT_EQ(ReadFile(la.Image(n, f)), ReadFile(lb.Image(n, f))) << "off must not change a byte";
      EXPECT_EQ(ReadFile(lc.Image(n, f)), ReadFile(ld.Image(n, f))) << "same seed, 1 or 2 threads";
      changed += ReadFile(la.Image(n, f)) != ReadFile(lc.Image(n, f));
      // Ground truth stays exact.
      for (const auto& path : {&DatasetLayout::Label, &DatasetLayout::LabelColor, &DatasetLayout::Instance, &DatasetLayout::Depth}) {
        EXPECT_EQ(ReadFile((la.*path)(n, f)), ReadFile((lc.*path)(n, f))) << (la.*path)(n, f);
      }
    }
  }
  EXPECT_EQ(changed, 6) << "every view, even cam2's sky, gets its camera's exposure and noise";
  EXPECT_EQ(ReadFile(la.OverlapJson()), ReadFile(lc.OverlapJson()));

  std::ifstream file(lc.PhotometricJson());
  const nlohmann::json j = nlohmann::json::parse(file);
  EXPECT_EQ(j.at("seed").get<uint64_t>(), 7u);
  EXPECT_EQ(j.at("options").at("read_noise_stddev").get<double>(), 0.01);
  ASSERT_EQ(j.at("cameras").size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const nlohmann::json& cam = j.at("cameras")[i];
    const CameraPhotometry drawn = DrawCameraPhotometry(on.photometric, i);
    EXPECT_EQ(cam.at("name"), plain.rig.cameras[i].name);
    EXPECT_EQ(cam.at("exposure_stops").get<double>(), drawn.exposure_stops);
    EXPECT_EQ(cam.at("gain").get<double>(), drawn.gain());
    EXPECT_EQ(cam.at("white_balance_rgb")[2].get<double>(), drawn.white_balance.z());
    EXPECT_EQ(cam.at("vignetting_strength").get<double>(), 0.3);
  }
  EXPECT_NE(j.at("cameras")[0].at("gain"), j.at("cameras")[1].at("gain"));

  // Bad options are refused before anything is written.
  RenderJob bad = on;
  bad.photometric.vignetting_strength = 1.2;
  EXPECT_THROW(RenderDataset(bad, scratch / "bad", false), std::invalid_argument);
  EXPECT_FALSE(fs::exists(scratch / "bad"));
}



// A sensor preset: "ideal" writes exactly the dataset of a job without it; another preset changes
// only the RGB images (deterministically), its values reach the renderer (photometric.json,
// sensor.json) and the ground truth stays exact.
TEST(RenderDatasetTest, SensorPresetChangesOnlyRgbAndIsRecorded) {
  const TempDir scratch;
  const Scene scene = WallScene();
  const RenderJob plain = WallJob(scene);
  RenderJob ideal = plain;
  ideal.sensor_preset = "ideal";
  const SensorPreset& preset = FindSensorPreset("automotive");
  RenderJob automotive = plain;
  automotive.sensor_preset = preset.name;
  automotive.photometric = preset.photometric;
  automotive.photometric.seed = 3;
  automotive.defocus = preset.defocus;
  automotive.defocus.pixel_pitch_um = 100;  // fx 30 px: f = 3 mm, a visible blur on the box at 3 m
  automotive.defocus.focus_distance_m = 0.1;
  automotive.jpeg_quality = preset.jpeg_quality;
  RenderJob again = automotive;
  again.options.num_threads = 1;
  const fs::path a = scratch / "plain", b = scratch / "ideal", c = scratch / "automotive", d = scratch / "again";
  RenderDataset(plain, a, false);
  RenderDataset(ideal, b, false);
  RenderDataset(automotive, c, false);
  RenderDataset(again, d, false);
  const DatasetLayout la(a), lb(b), lc(c), ld(d);
  EXPECT_FALSE(fs::exists(lb.SensorJson()));
  EXPECT_FALSE(fs::exists(lb.PhotometricJson()));
  for (const RigCamera& cam : plain.rig.cameras) {
    for (const Frame& frame : plain.frames.frames) {
      const std::string& n = cam.name;
      const std::string& f = frame.name;
      EXPECT_EQ(ReadFile(la.Image(n, f)), ReadFile(lb.Image(n, f))) << "ideal must not change a byte";
      EXPECT_NE(ReadFile(la.Image(n, f)), ReadFile(lc.Image(n, f)));
      EXPECT_EQ(ReadFile(lc.Image(n, f)), ReadFile(ld.Image(n, f))) << "same seed, same bytes";
      for (const auto& path : {&DatasetLayout::Label, &DatasetLayout::LabelColor, &DatasetLayout::Instance, &DatasetLayout::Depth}) {
        EXPECT_EQ(ReadFile((la.*path)(n, f)), ReadFile((lc.*path)(n, f))) << (la.*path)(n, f);
      }
    }
  }
  ASSERT_TRUE(fs::exists(lc.SensorJson()));
  std::ifstream sensor_file(lc.SensorJson());
  const nlohmann::json s = nlohmann::json::parse(sensor_file);
  EXPECT_EQ(s.at("preset"), "automotive");
  EXPECT_EQ(s.at("jpeg_quality").get<int>(), 75);
  EXPECT_EQ(s.at("defocus").at("f_number").get<double>(), preset.defocus.f_number);
  EXPECT_EQ(s.at("stages"), nlohmann::json({"exposure and white balance", "vignetting", "defocus", "shot and read noise",
                                            "8-bit sRGB", "JPEG"}));
  std::ifstream photometric_file(lc.PhotometricJson());
  const nlohmann::json p = nlohmann::json::parse(photometric_file);
  EXPECT_EQ(p.at("options").at("shot_noise").get<double>(), preset.photometric.shot_noise);
  EXPECT_EQ(p.at("options").at("vignetting_strength").get<double>(), preset.photometric.vignetting_strength);

  RenderJob bad = automotive;
  bad.jpeg_quality = 101;
  EXPECT_THROW(RenderDataset(bad, scratch / "bad", false), std::invalid_argument);
  bad = automotive;
  bad.defocus.focus_distance_m = 0.001;  // inside the 3 mm focal length
  EXPECT_THROW(RenderDataset(bad, scratch / "bad", false), std::invalid_argument);
  EXPECT_FALSE(fs::exists(scratch / "bad"));
}

// Five frames, every extra output, photometric differences and a rolling-shutter camera: all that
// a shard must reproduce of the frames it renders and the merge of what spans frames.
RenderJob EverythingJob(const Scene& scene) {
  RenderJob job = WallJob(scene);
  for (int f = 2; f < 5; ++f) {
    Frame frame = job.frames.frames[1];
    frame.name = "00000" + std::to_string(f);
    frame.rig_from_world = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.2 * f, 0.05 * f, 0));
    frame.timestamp_s = 0.1 * f;
    job.frames.frames.push_back(frame);
  }
  job.rig.cameras[1].readout_s = 0.02;
  job.options.samples_per_pixel = 4;
  job.photometric.exposure_stops_sigma = 0.3;
  job.photometric.shot_noise = 1e-4;
  job.photometric.seed = 7;
  job.extras = {true, true, true, true};
  return job;
}

TEST(RenderShardsTest, MergedShardsAreByteIdenticalToOneRender) {
  const TempDir dir;
  const Scene scene = WallScene();
  const RenderJob whole = EverythingJob(scene);
  RenderDataset(whole, dir / "whole", false);
  std::vector<fs::path> shards;
  for (int i = 0; i < 3; ++i) {
    RenderJob part = whole;
    part.shard = {i, 3};
    RenderDataset(part, dir / ("shard" + std::to_string(i)), false);
    shards.push_back(dir / ("shard" + std::to_string(i)));
  }
  // A shard is a dataset of its own frames.
  EXPECT_EQ(ReadFrames(DatasetLayout(shards[1]).FramesJson()).frames.size(), 2u);  // frames 1-2 of 0-4 (1, 2, 2)
  EXPECT_TRUE(fs::exists(DatasetLayout(shards[1]).Image("cam0", "000002")));
  EXPECT_FALSE(fs::exists(DatasetLayout(shards[1]).Image("cam0", "000003")));
  MergeRenderShards(dir / "merged", {shards[2], shards[0], shards[1]}, false);
  const auto expected = FilesUnder(dir / "whole"), merged = FilesUnder(dir / "merged");
  ASSERT_GT(expected.size(), 80u);
  EXPECT_TRUE(expected.count("poses.json") && expected.count("instances_coco.json") && expected.count("photometric.json"));
  EXPECT_TRUE(expected.count("flow/cam0/000002.exr")) << "the flow from a shard's first frame's predecessor";
  for (const auto& [name, bytes] : expected) {
    ASSERT_TRUE(merged.count(name)) << name;
    EXPECT_TRUE(merged.at(name) == bytes) << name << " differs";
  }
  EXPECT_EQ(merged.size(), expected.size());
}

TEST(RenderShardsTest, TheMergeRefusesGapsRepeatsAndOtherRendersAndWritesNothing) {
  const TempDir dir;
  const Scene scene = WallScene();
  RenderJob job = WallJob(scene);
  std::vector<fs::path> shards;
  for (int i = 0; i < 2; ++i) {
    RenderJob part = job;
    part.shard = {i, 2};
    RenderDataset(part, dir / ("s" + std::to_string(i)), false);
    shards.push_back(dir / ("s" + std::to_string(i)));
  }
  RenderJob other = job;
  other.options.seed = 43;
  other.shard = {1, 2};
  RenderDataset(other, dir / "other", false);
  const auto refused = [&](const std::vector<fs::path>& dirs, const std::string& says) {
    try {
      MergeRenderShards(dir / "merged", dirs, false);
      ADD_FAILURE() << "merged; expected: " << says;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "merged"));
  };
  refused({shards[0]}, "shards 1 of 2 are missing");
  refused({shards[0], shards[0]}, "shard 0 is also");
  refused({shards[0], dir / "other"}, (dir / "other").string() + ": a shard of another render");
  refused({shards[0], dir / "whole_missing"}, "no shard.json");
  MergeRenderShards(dir / "merged", shards, false);
  EXPECT_EQ(ReadFrames(DatasetLayout(dir / "merged").FramesJson()).frames.size(), 2u);
  EXPECT_FALSE(fs::exists(dir / "merged" / "shard.json"));
}

}  // namespace
}  // namespace rigsim
