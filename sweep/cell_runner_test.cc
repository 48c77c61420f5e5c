#include "sweep/cell_runner.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "common/data_dir.h"
#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "geometry/rig.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

constexpr int kEgoVehicleLabel = 1;  // Cityscapes 'ego vehicle'
constexpr int kRoadLabel = 7;        // Cityscapes 'road'

int CountLabel(const ImageU8& label, int id, int y_begin, int y_end) {
  int n = 0;
  for (int y = y_begin; y < y_end; ++y) {
    for (int x = 0; x < label.width; ++x) n += label.at(x, y) == id;
  }
  return n;
}

// A cell with placement road and ego_vehicle renders the rig as make-rig --placement road
// --ego-vehicle and render do: in its lane on the shipped street (which runs along world z, its road
// at y = 0), heading along it with its origin the rig's height above the road, and its own car in
// the side views' lower half. The same cell without them stands where structure placement puts it,
// without a car.
TEST(CellRunner, PlacementRoadDrivesTheLaneAndEgoVehicleBringsTheCar) {
  const TempDir dir;
  Json j = Json::parse(R"({
    "base": {"rig": "surround", "width": 48, "height": 32, "frames": 2, "trajectory": "straight", "step": 1.0, "spp": 1},
    "methods": {"semantics": ["none"]},
    "zip": {"placement": ["structure", "road"], "ego_vehicle": [false, true]}})");
  j["base"]["scene"] = DataPath("assets/scenes/street.glb").string();
  const SweepConfig config = ParseSweepConfig(j, "t.json");
  const std::vector<SweepCell> cells = ExpandCells(config);
  ASSERT_EQ(cells.size(), 2u);
  CellRunnerOptions options;
  options.config_dir = dir.path();
  options.scene_dir = dir / "scenes";
  options.num_threads = 1;
  const CellRunner run = MakeCellRunner(config, options);
  for (const SweepCell& cell : cells) {
    const bool road = CellParam(cell.params, "placement") == "road";
    SCOPED_TRACE(road ? "road" : "structure");
    const fs::path work = dir / cell.key;
    fs::create_directories(work);
    const CellRecord record = run(cell, work, [](const std::string&) {});
    ASSERT_EQ(record.rows.size(), 1u);
    EXPECT_EQ(record.rows[0].failure_reason.find("place"), std::string::npos) << record.rows[0].failure_reason;
    const DatasetLayout layout(work / "dataset");
    const Rig rig = ReadRig(work / "dataset/rig.json");
    const FramesFile frames = ReadFrames(work / "dataset/frames.json");
    ASSERT_EQ(frames.frames.size(), 2u);
    for (const Frame& f : frames.frames) {
      const Rigid3d world_from_rig = f.rig_from_world->Inverse();
      const Eigen::Vector3d forward = world_from_rig.rotation * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d down = world_from_rig.rotation * Eigen::Vector3d::UnitY();
      EXPECT_NEAR(down.y(), -1.0, 1e-9) << "the rig stands upright";
      if (!road) continue;
      EXPECT_GT(std::abs(forward.z()), std::cos(1.0 * M_PI / 180)) << "heading along the street";
      EXPECT_NEAR(world_from_rig.translation.y(), PlacementOptions{}.height_m, 1e-6);
    }
    for (const std::string cam : {"left", "right"}) {
      const ImageU8 label = ReadImageU8(layout.Label(cam, "000000"), 1);
      EXPECT_EQ(CountLabel(label, kEgoVehicleLabel, 0, label.height / 2), 0) << cam;
      if (road) {
        EXPECT_GT(CountLabel(label, kEgoVehicleLabel, label.height / 2, label.height), label.width) << cam;
      } else {
        EXPECT_EQ(CountLabel(label, kEgoVehicleLabel, 0, label.height), 0) << cam;
      }
    }
    if (road) {  // in its lane the back camera looks down the road behind it, past its car
      const ImageU8 back = ReadImageU8(layout.Label("back", "000000"), 1);
      EXPECT_GT(CountLabel(back, kRoadLabel, 0, back.height), back.width) << "the road behind";
    }
  }
}

// A rig with a camera looking down into where its car would be: the cell fails naming the camera,
// before anything renders, as make-rig --ego-vehicle refuses it (in its lane: structure placement
// finds no place for a camera that looks at the ground).
TEST(CellRunner, ACameraLookingIntoTheCarFailsTheCell) {
  const TempDir dir;
  Rig rig;
  // Cameras at the roof's front and rear edges looking out keep the roof 5 cm under them (no mount),
  // and the third looks straight down at it.
  const Camera camera(CameraModelId::kPinhole, 32, 24, {20, 20, 15.5, 11.5});
  const Eigen::Quaterniond looks_back(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()));
  const Eigen::Quaterniond looks_down(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));  // its z along rig +y
  const auto at = [](const Eigen::Quaterniond& cam_from_rig, const Eigen::Vector3d& centre) {
    return Rigid3d(cam_from_rig, -(cam_from_rig * centre));
  };
  rig.cameras = {{"ahead", camera, Rigid3d(), 0.0},
                 {"behind", camera, at(looks_back, {0, 0, -1.8}), 0.0},
                 {"down", camera, at(looks_down, {0.3, 0, -0.9}), 0.0}};
  WriteRig(rig, dir / "rig.json");
  Json j = Json::parse(R"({"base": {"rig": "file", "rig_file": "rig.json", "frames": 1, "spp": 1,
                                    "placement": "road", "ego_vehicle": true},
                           "methods": {"semantics": ["none"]}})");
  j["base"]["scene"] = DataPath("assets/scenes/street.glb").string();
  const SweepConfig config = ParseSweepConfig(j, "t.json");
  CellRunnerOptions options;
  options.config_dir = dir.path();
  options.scene_dir = dir / "scenes";
  options.num_threads = 1;
  const SweepCell cell = ExpandCells(config).at(0);
  const Eigen::Vector3d down_axis = rig.cameras[2].cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ();
  ASSERT_TRUE(down_axis.isApprox(Eigen::Vector3d::UnitY()));
  const CellRecord record = MakeCellRunner(config, options)(cell, dir.path(), [](const std::string&) {});
  ASSERT_EQ(record.rows.size(), 1u);
  EXPECT_EQ(record.rows[0].status, "failed");
  EXPECT_EQ(record.rows[0].failure_reason.rfind("ego_vehicle: camera 'down' looks into the car body", 0), 0u)
      << record.rows[0].failure_reason;
  EXPECT_FALSE(fs::exists(dir / "dataset"));
}

}  // namespace
}  // namespace rigsim
