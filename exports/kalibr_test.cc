#include "exports/kalibr.h"

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "exports/test_rig.h"

namespace rigsim {
namespace {

// Minimal reader of the camchain layout we write: camN -> key -> list of numbers (or text).
struct KalibrCam {
  std::map<std::string, std::vector<double>> lists;
  std::map<std::string, std::string> text;
  std::vector<std::vector<double>> t_cn_cnm1;
};

std::vector<double> ParseList(const std::string& s) {
  std::vector<double> v;
  std::string body = s.substr(s.find('[') + 1);
  body = body.substr(0, body.find(']'));
  std::stringstream ss(body);
  for (std::string item; std::getline(ss, item, ',');) v.push_back(std::stod(item));
  return v;
}

std::vector<KalibrCam> Parse(const std::string& yaml) {
  std::vector<KalibrCam> cams;
  std::istringstream in(yaml);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] != ' ') {
      cams.emplace_back();
      continue;
    }
    if (line.rfind("  - ", 0) == 0) {
      cams.back().t_cn_cnm1.push_back(ParseList(line));
      continue;
    }
    const size_t colon = line.find(':');
    const std::string key = line.substr(2, colon - 2), value = line.substr(colon + 1);
    if (value.find('[') != std::string::npos) cams.back().lists[key] = ParseList(value);
    else cams.back().text[key] = value.empty() ? "" : value.substr(1);
  }
  return cams;
}

TEST(Kalibr, ChainComposesBackToCamFromRig) {
  const Rig rig = test::MixedRig();
  const std::vector<KalibrCam> cams = Parse(KalibrCamchainYaml(rig));
  ASSERT_EQ(cams.size(), 3u);
  EXPECT_TRUE(cams[0].t_cn_cnm1.empty());  // cam0 is the start of the chain
  // cam_n_from_cam0 = T_n * T_{n-1} * ... * T_1 must equal cam_from_rig[n] * cam_from_rig[0]^-1.
  Eigen::Matrix4d cn_from_c0 = Eigen::Matrix4d::Identity();
  for (size_t n = 1; n < cams.size(); ++n) {
    ASSERT_EQ(cams[n].t_cn_cnm1.size(), 4u);
    Eigen::Matrix4d t;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) t(r, c) = cams[n].t_cn_cnm1[r][c];
    }
    cn_from_c0 = t * cn_from_c0;
    const Rigid3d expected = *rig.cameras[n].cam_from_rig * rig.cameras[0].cam_from_rig->Inverse();
    Eigen::Matrix4d e = Eigen::Matrix4d::Identity();
    e.topRows<3>() = expected.ToMatrix();
    EXPECT_LT((cn_from_c0 - e).cwiseAbs().maxCoeff(), 1e-12) << "cam" << n;
  }
}

TEST(Kalibr, IntrinsicsAndDistortionOrder) {
  const Rig rig = test::MixedRig();
  const std::vector<KalibrCam> cams = Parse(KalibrCamchainYaml(rig));
  // cam0 OPENCV: radtan [k1 k2 r1 r2] = our k1 k2 p1 p2; intrinsics [fu fv pu pv] without any shift.
  EXPECT_EQ(cams[0].text.at("camera_model"), "pinhole");
  EXPECT_EQ(cams[0].text.at("distortion_model"), "radtan");
  EXPECT_EQ(cams[0].lists.at("intrinsics"), (std::vector<double>{500, 510, 319.5, 239.5}));
  EXPECT_EQ(cams[0].lists.at("distortion_coeffs"), (std::vector<double>{-0.2, 0.05, 0.001, -0.002}));
  EXPECT_EQ(cams[0].lists.at("resolution"), (std::vector<double>{640, 480}));
  // cam1 PINHOLE: radtan with zeros.
  EXPECT_EQ(cams[1].lists.at("distortion_coeffs"), (std::vector<double>{0, 0, 0, 0}));
  // cam2 fisheye: equidistant [k1 k2 k3 k4].
  EXPECT_EQ(cams[2].text.at("distortion_model"), "equidistant");
  EXPECT_EQ(cams[2].lists.at("distortion_coeffs"), (std::vector<double>{0.01, -0.02, 0.003, -0.001}));
  EXPECT_EQ(cams[2].text.at("rostopic"), "/cam2/image_raw");
}

TEST(Kalibr, RejectsWhatKalibrCannotExpress) {
  Rig rig = test::MixedRig();
  rig.cameras[1].cam_from_rig.reset();
  EXPECT_THROW(KalibrCamchainYaml(rig), std::invalid_argument);
  rig = test::MixedRig();
  rig.cameras[1].camera = Camera(CameraModelId::kFullOpenCV, 800, 600, {600, 600, 400, 300, 0.1, 0.01, 0, 0, 0.001, 0.2, 0, 0});
  EXPECT_THROW(KalibrCamchainYaml(rig), std::invalid_argument);
  rig.cameras[1].camera = Camera(CameraModelId::kFullOpenCV, 800, 600, {600, 600, 400, 300, 0.1, 0.01, 0, 0, 0, 0, 0, 0});
  EXPECT_NO_THROW(KalibrCamchainYaml(rig));
}

}  // namespace
}  // namespace rigsim
