#include <cstdio>

#include "apps/rigsim/commands.h"
#include "geometry/rig.h"
#include "scenes/rig_generators.h"

namespace rigsim::cli {

void AddMakeRigCommand(CLI::App& app) {
  struct Args {
    RingRigOptions ring;
    std::vector<double> position = {0.0, 1.6, 0.0};
    double heading_deg = 0.0;
    int frames = 1;
    double step_m = 2.0;
    std::string rig_out, frames_out;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "make-rig",
      "Write a ring rig (rig.json) and its placement in a scene (frames.json) for `rigsim render`.\n"
      "Cameras cam0..camN-1 sit on a horizontal circle facing outwards, left to right.");
  RingRigOptions& r = args->ring;
  cmd->add_option("--cameras", r.num_cameras, "number of cameras")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--spacing", r.yaw_spacing_deg, "yaw between neighbouring cameras (deg)")->capture_default_str();
  cmd->add_option("--hfov", r.hfov_deg, "horizontal field of view of each camera (deg)")->capture_default_str();
  cmd->add_option("--radius", r.radius_m, "radius of the ring (m)")->capture_default_str();
  cmd->add_option("--width", r.width, "image width (px)")->capture_default_str();
  cmd->add_option("--height", r.height, "image height (px)")->capture_default_str();
  cmd->add_option("--distorted", r.distorted_camera, "index of the camera with barrel distortion (-1 = none)")
      ->capture_default_str();
  cmd->add_option("--k1", r.k1, "its OPENCV k1")->capture_default_str();
  cmd->add_option("--k2", r.k2, "its OPENCV k2")->capture_default_str();
  cmd->add_option("--position", args->position, "rig position in the world at frame 0: x,y,z (m, glTF +Y up)")
      ->delimiter(',')
      ->expected(3)
      ->capture_default_str();
  cmd->add_option("--heading", args->heading_deg, "rig heading (deg; 0 = world -Z, 90 = world +X)")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "number of frames; the rig moves forward between them")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--step", args->step_m, "distance moved per frame (m)")->capture_default_str();
  cmd->add_option("--rig-out", args->rig_out, "rig.json to write")->required();
  cmd->add_option("--frames-out", args->frames_out, "frames.json to write")->required();
  cmd->callback([args] {
    const Rig rig = MakeRingRig(args->ring);
    const Eigen::Vector3d start(args->position[0], args->position[1], args->position[2]);
    const FramesFile frames = MakeStraightTrajectory(start, args->heading_deg, args->frames, args->step_m);
    WriteRig(rig, args->rig_out);
    WriteFrames(frames, args->frames_out);
    std::printf("wrote %s (%zu cameras) and %s (%zu frames)\n", args->rig_out.c_str(), rig.cameras.size(),
                args->frames_out.c_str(), frames.frames.size());
  });
}

}  // namespace rigsim::cli
