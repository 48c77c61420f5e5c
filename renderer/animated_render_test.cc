// Rendering an animated scene: each camera sees the scene posed at its own time
// (scene/scene_pose.h), and the result does not depend on the number of threads.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "renderer/render_dataset.h"
#include "renderer/renderer.h"
#include "scene/scene_pose.h"
#include "scene/test_scenes.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

// Mean x of the pixels showing `instance`; -1 when none.
double InstanceCentroidX(const ImageU16& instance, uint16_t id) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < instance.height; ++y) {
    for (int x = 0; x < instance.width; ++x) {
      if (instance.at(x, y) == id) {
        sum += x;
        ++n;
      }
    }
  }
  return n > 0 ? sum / n : -1.0;
}

const Camera& TestCamera() {
  static const Camera camera(CameraModelId::kPinhole, 160, 120, {100, 100, 79.5, 59.5});
  return camera;
}
TEST(AnimatedRenderTest, MovingBoxRendersWhereItIsAtEachTime) {
  const Scene scene = AnimatedBoxScene();
  Renderer renderer(scene);
  const Camera& camera = TestCamera();
  for (double t : {0.0, 1.0}) {
    const std::vector<SceneMesh> posed = PoseMeshesAt(scene, t);
    renderer.SetMeshes(posed);
    const RenderedView view = renderer.Render(camera, Rigid3d(), RenderOptions());
    const double x_centre = t == 0.0 ? -1.0 : 1.0;
    // The box's image is nearly symmetric about the projection of its centre (front face nearer).
    const double expected = camera.ImgFromCam(Eigen::Vector3d(x_centre, 0, 6))->x();
    EXPECT_NEAR(InstanceCentroidX(view.instance, 5), expected, 1.5) << "t = " << t;
  }
}

RenderJob TwoCameraJob(const Scene& scene, double offset_b) {
  RenderJob job;
  job.scene = &scene;
  job.scene_name = "animated box";
  job.rig.cameras.push_back({"early", TestCamera(), Rigid3d(), 0.0});
  job.rig.cameras.push_back({"late", TestCamera(), Rigid3d(), offset_b});
  Frame f0{"000000", Rigid3d(), 0.25};
  Frame f1{"000001", Rigid3d(), 0.5};
  job.frames.frames = {f0, f1};
  job.options.samples_per_pixel = 4;
  job.options.seed = 3;
  return job;
}

TEST(AnimatedRenderTest, UnsynchronisedCamerasSeeTheBoxInDifferentPlaces) {
  const Scene scene = AnimatedBoxScene();
  const TempDir scratch;
  const auto dir = scratch / "unsynchronised";
  RenderDataset(TwoCameraJob(scene, 0.5), dir, true);
  const DatasetLayout layout(dir);
  // Frame 0 at 0.25 s: "early" sees the box at x = -0.5, "late" (0.75 s) at x = +0.5.
  const double early = InstanceCentroidX(ReadImageU16(layout.Instance("early", "000000")), 5);
  const double late = InstanceCentroidX(ReadImageU16(layout.Instance("late", "000000")), 5);
  EXPECT_NEAR(early, TestCamera().ImgFromCam(Eigen::Vector3d(-0.5, 0, 6))->x(), 1.5);
  EXPECT_NEAR(late, TestCamera().ImgFromCam(Eigen::Vector3d(0.5, 0, 6))->x(), 1.5);
  // Frame 1 at 0.5 s: "early" sees it at x = 0, "late" (1.0 s) at x = 1.
  EXPECT_NEAR(InstanceCentroidX(ReadImageU16(layout.Instance("early", "000001")), 5),
              TestCamera().ImgFromCam(Eigen::Vector3d(0, 0, 6))->x(), 1.5);
  EXPECT_NEAR(InstanceCentroidX(ReadImageU16(layout.Instance("late", "000001")), 5),
              TestCamera().ImgFromCam(Eigen::Vector3d(1, 0, 6))->x(), 1.5);
  // Synchronised cameras with the same pose see the same image.
  const auto sync_dir = scratch / "synchronised";
  RenderDataset(TwoCameraJob(scene, 0.0), sync_dir, true);
  const DatasetLayout sync(sync_dir);
  EXPECT_EQ(ReadFile(sync.Image("early", "000000")), ReadFile(sync.Image("late", "000000")));
}

TEST(AnimatedRenderTest, AnimatedDatasetIsByteIdenticalWithOneAndTwoThreads) {
  const Scene scene = AnimatedBoxScene();
  RenderJob job = TwoCameraJob(scene, 0.3);
  job.options.num_threads = 1;
  const TempDir scratch;
  const auto one = scratch / "threads1";
  RenderDataset(job, one, true);
  job.options.num_threads = 2;
  const auto two = scratch / "threads2";
  RenderDataset(job, two, true);
  const DatasetLayout a(one), b(two);
  for (const std::string cam : {"early", "late"}) {
    for (const std::string frame : {"000000", "000001"}) {
      EXPECT_EQ(ReadFile(a.Image(cam, frame)), ReadFile(b.Image(cam, frame))) << cam << " " << frame;
      EXPECT_EQ(ReadFile(a.Label(cam, frame)), ReadFile(b.Label(cam, frame))) << cam << " " << frame;
      EXPECT_EQ(ReadFile(a.Instance(cam, frame)), ReadFile(b.Instance(cam, frame))) << cam << " " << frame;
      EXPECT_EQ(ReadFile(a.Depth(cam, frame)), ReadFile(b.Depth(cam, frame))) << cam << " " << frame;
    }
  }
  EXPECT_EQ(ReadFile(a.OverlapJson()), ReadFile(b.OverlapJson()));
}

}  // namespace
}  // namespace rigsim
