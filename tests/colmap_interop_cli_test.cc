// The COLMAP export with COLMAP's own tools, end to end: a small rendered dataset exported with
// `rigsim export --format colmap`, then the export's triangulate.sh (feature_extractor per camera,
// exhaustive_matcher, point_triangulator on the exported poses). point_triangulator must succeed
// and triangulate points that the exported cameras and poses reproject within a pixel. Skipped
// when colmap is not on the PATH (scripts/install-deps.sh --tests installs it).
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

// Data lines of a COLMAP text file: neither comments nor empty lines.
std::vector<std::string> DataLines(const fs::path& path) {
  std::vector<std::string> lines;
  std::istringstream in(ReadFile(path));
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  return lines;
}

// `command` through the shell; its exit code.
int Shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(ColmapInterop, PointTriangulatorRunsOnTheExport) {
  if (Shell("command -v colmap > /dev/null 2>&1") != 0) GTEST_SKIP() << "colmap is not on the PATH";
  const TempDir temp;
  const fs::path dir = temp.path();
  const std::string street = std::string(RIGSIM_SOURCE_DIR) + "/assets/scenes/street.glb";
  // 3 cameras (cam1 with OPENCV distortion) x 2 frames at 320x240, placed in the street.
  CliResult r = RunRigsim({"make-rig", "ring", "--cameras", "3", "--spacing", "50", "--hfov", "90", "--width", "320", "--height",
                           "240", "--frames", "2", "--step", "1", "--scene", street, "--out", (dir / "rig").string()},
                          dir / "make_rig");
  ASSERT_EQ(r.code, 0) << r.err;
  r = RunRigsim({"render", "--scene", street, "--rig", (dir / "rig" / "rig.json").string(), "--frames",
                 (dir / "rig" / "frames.json").string(), "--out", (dir / "data").string(), "--spp", "1"},
                dir / "render");
  ASSERT_EQ(r.code, 0) << r.err;
  r = RunRigsim({"export", (dir / "data").string(), "--format", "colmap", "--out", (dir / "export").string()}, dir / "export");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("bash " + (dir / "export" / "colmap" / "triangulate.sh").string()), std::string::npos) << r.out;

  const fs::path out = dir / "triangulated";
  const int code = Shell("bash " + (dir / "export" / "colmap" / "triangulate.sh").string() + " " + (dir / "data" / "images").string() +
                         " " + out.string() + " > " + (dir / "triangulate.log").string() + " 2>&1");
  ASSERT_EQ(code, 0) << ReadFile(dir / "triangulate.log") << ReadFile(out / "colmap.log");
  EXPECT_EQ(DataLines(out / "model" / "images.txt").size(), 2u * 6u);  // pose and points line per image
  const std::vector<std::string> points = DataLines(out / "model" / "points3D.txt");
  EXPECT_GT(points.size(), 50u) << ReadFile(dir / "triangulate.log");
  // POINT3D_ID X Y Z R G B ERROR ...: the exported intrinsics and poses explain the matches.
  std::vector<double> errors;
  for (const std::string& line : points) {
    std::istringstream fields(line);
    double id, x, y, z, red, green, blue, error;
    if (fields >> id >> x >> y >> z >> red >> green >> blue >> error) errors.push_back(error);
  }
  ASSERT_EQ(errors.size(), points.size());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  EXPECT_LT(errors[errors.size() / 2], 1.0) << "median reprojection error, px";

  // A second run into the same folder is refused: it would mix two databases.
  EXPECT_NE(Shell("bash " + (dir / "export" / "colmap" / "triangulate.sh").string() + " " + (dir / "data" / "images").string() + " " +
                  out.string() + " > /dev/null 2>&1"),
            0);
}

}  // namespace
}  // namespace rigsim
