#include "exports/rig_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rigsim {
namespace {

// A camera in the first camera's frame.
struct Placed {
  std::optional<Eigen::Vector3d> centre;
  std::optional<Eigen::Matrix3d> cam0_from_cam;
};

// cam_from_cam0 = cam_from_rig * cam0_from_rig^-1 for every camera with a pose.
std::vector<Placed> InFirstCameraFrame(const Rig& rig, const std::string& which) {
  if (rig.cameras.empty() || !rig.cameras[0].cam_from_rig) {
    throw std::invalid_argument("rig plot: the " + which + "'s first camera has no pose");
  }
  const Rigid3d rig_from_cam0 = rig.cameras[0].cam_from_rig->Inverse();
  std::vector<Placed> placed(rig.cameras.size());
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    if (!rig.cameras[c].cam_from_rig) continue;
    const Rigid3d cam_from_cam0 = *rig.cameras[c].cam_from_rig * rig_from_cam0;
    placed[c].centre = cam_from_cam0.SourceOriginInTarget();
    placed[c].cam0_from_cam = cam_from_cam0.RotationMatrix().transpose();
  }
  return placed;
}

std::string Escape(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string Fixed(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

// 1, 2 or 5 times a power of ten, near `target`.
double NiceLength(double target) {
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * p >= target * 0.7) return m * p;
  }
  return 10 * p;
}

void CheckSameCameras(const RigPlotInput& in) {
  const size_t n = in.estimate.cameras.size();
  if (in.truth && in.truth->cameras.size() != n) {
    throw std::invalid_argument("rig plot: the truth has " + std::to_string(in.truth->cameras.size()) +
                                " cameras, the estimate " + std::to_string(n));
  }
  for (size_t c = 0; in.truth && c < n; ++c) {
    if (in.truth->cameras[c].name != in.estimate.cameras[c].name) {
      throw std::invalid_argument("rig plot: camera " + std::to_string(c) + " is '" + in.estimate.cameras[c].name +
                                  "' in the estimate but '" + in.truth->cameras[c].name + "' in the truth");
    }
  }
}

// Scales the estimate's centres by the s that minimises sum |s * e - t|^2 over the cameras both place.
void ScaleToTruth(const std::vector<Placed>& truth, std::vector<Placed>* estimate) {
  double et = 0, ee = 0;
  for (size_t c = 0; c < truth.size(); ++c) {
    if ((*estimate)[c].centre && truth[c].centre) {
      et += (*estimate)[c].centre->dot(*truth[c].centre);
      ee += (*estimate)[c].centre->squaredNorm();
    }
  }
  const double s = ee > 1e-18 ? et / ee : 1.0;
  for (Placed& p : *estimate) {
    if (p.centre) *p.centre *= s;
  }
}

}  // namespace

std::string RigTopDownSvg(const RigPlotInput& in) {
  CheckSameCameras(in);
  const size_t n = in.estimate.cameras.size();
  std::vector<Placed> estimate = InFirstCameraFrame(in.estimate, "estimate");
  const std::vector<Placed> truth = in.truth ? InFirstCameraFrame(*in.truth, "truth") : std::vector<Placed>(n);
  const Rigid3d cam0_from_rig = *in.estimate.cameras[0].cam_from_rig;

  // A unit-scale estimate takes the truth's scale.
  const bool in_metres = in.metric || in.truth;
  if (!in.metric && in.truth) ScaleToTruth(truth, &estimate);

  // Extent of every centre drawn, in the page's (x, z).
  double xmin = 1e300, xmax = -1e300, zmin = 1e300, zmax = -1e300;
  auto extend = [&](const Eigen::Vector3d& p) {
    xmin = std::min(xmin, p.x()), xmax = std::max(xmax, p.x());
    zmin = std::min(zmin, p.z()), zmax = std::max(zmax, p.z());
  };
  for (size_t c = 0; c < n; ++c) {
    if (estimate[c].centre) extend(*estimate[c].centre);
    if (truth[c].centre) extend(*truth[c].centre);
  }
  const double span = std::max({xmax - xmin, zmax - zmin, 1e-6});
  const double arm = (xmax - xmin < 1e-6 && zmax - zmin < 1e-6) ? 1.0 : 0.25 * span;  // direction line length
  xmin -= arm, xmax += arm, zmin -= arm, zmax += arm;

  constexpr double kSize = 720, kMargin = 60, kTop = 90;
  const double scale = (kSize - 2 * kMargin) / std::max(xmax - xmin, zmax - zmin);
  // The narrower direction centred on the page.
  const double x0 = kMargin + 0.5 * ((kSize - 2 * kMargin) - scale * (xmax - xmin));
  const double y0 = kTop + 0.5 * ((kSize - 2 * kMargin) - scale * (zmax - zmin));
  auto page = [&](const Eigen::Vector3d& p) {
    return std::array<double, 2>{x0 + scale * (p.x() - xmin), y0 + scale * (zmax - p.z())};
  };
  std::string svg;
  auto line = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const std::string& style) {
    const auto pa = page(a), pb = page(b);
    svg += "<line x1=\"" + Fixed(pa[0]) + "\" y1=\"" + Fixed(pa[1]) + "\" x2=\"" + Fixed(pb[0]) + "\" y2=\"" +
           Fixed(pb[1]) + "\" " + style + "/>\n";
  };
  // Direction, and the field of view's edges at the principal row (through the lens model, so a
  // fisheye's wedge opens beyond 180 degrees).
  auto camera_lines = [&](const Camera& camera, const Eigen::Vector3d& centre, const Eigen::Matrix3d& cam0_from_cam,
                          const std::string& colour, const std::string& extra) {
    for (const double x : {0.0, double(camera.width() - 1)}) {
      if (const auto b = camera.CamFromImg(Eigen::Vector2d(x, camera.cy()))) {
        line(centre, centre + 0.6 * arm * (cam0_from_cam * b->normalized()),
             "stroke=\"" + colour + "\" stroke-opacity=\"0.45\" stroke-width=\"1\"" + extra);
      }
    }
    line(centre, centre + arm * cam0_from_cam.col(2), "stroke=\"" + colour + "\" stroke-width=\"2\"" + extra);
  };
  auto circle = [&](const Eigen::Vector3d& centre, const std::string& cls, const std::string& name,
                    const std::string& colour, double r) {
    const auto p = page(centre);
    svg += "<circle class=\"" + cls + "\" data-camera=\"" + Escape(name) + "\" cx=\"" + Fixed(p[0]) + "\" cy=\"" +
           Fixed(p[1]) + "\" r=\"" + Fixed(r) + "\" fill=\"" + colour + "\"/>\n";
  };
  auto label = [&](const Eigen::Vector3d& centre, const std::string& name, const std::string& colour, double dy) {
    const auto p = page(centre);
    svg += "<text x=\"" + Fixed(p[0] + 8) + "\" y=\"" + Fixed(p[1] + dy) + "\" fill=\"" + colour + "\">" +
           Escape(name) + "</text>\n";
  };

  const std::string kTruth = "#888888", kEstimate = "#1f5fbf", kRotationOnly = "#d2691e";
  for (size_t c = 0; c < n; ++c) {
    const std::string& name = in.estimate.cameras[c].name;
    const Camera& camera = in.estimate.cameras[c].camera;
    if (truth[c].centre) {
      camera_lines(camera, *truth[c].centre, *truth[c].cam0_from_cam, kTruth, "");
      circle(*truth[c].centre, "truth", name, kTruth, 6);
      if (!estimate[c].centre) label(*truth[c].centre, name, kTruth, 16);
    }
    if (estimate[c].centre) {
      camera_lines(camera, *estimate[c].centre, *estimate[c].cam0_from_cam, kEstimate, "");
      circle(*estimate[c].centre, "estimate", name, kEstimate, 4);
      label(*estimate[c].centre, name, kEstimate, -8);
    } else if (c < in.rotation_only.size() && in.rotation_only[c] && truth[c].centre) {
      // cam_from_cam0 = cam_from_rig * rig_from_cam0 in the estimate's frame.
      const Eigen::Matrix3d cam_from_cam0 = (*in.rotation_only[c] * cam0_from_rig.rotation.conjugate()).toRotationMatrix();
      camera_lines(camera, *truth[c].centre, cam_from_cam0.transpose(), kRotationOnly, " stroke-dasharray=\"6 4\"");
    }
  }

  // Scale bar, legend and title.
  const double bar = NiceLength(span > 1e-6 ? span / 5 : 1.0);
  const double bar_x = kMargin, bar_y = kSize + kTop - kMargin + 25;
  char bar_text[64];
  std::snprintf(bar_text, sizeof(bar_text), "%g %s", bar, in_metres ? "m" : "units");
  std::string legend = "Blue: estimate.";
  if (in.truth) legend += in.metric ? " Grey: truth." : " Grey: truth (the estimate scaled to it).";
  legend += " Dashed: rotation only, at the true centre.";
  const std::string head =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Fixed(kSize) + "\" height=\"" + Fixed(kSize + kTop) +
      "\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      "<text x=\"" + Fixed(kMargin) + "\" y=\"24\" font-size=\"16\">" + Escape(in.title) + "</text>\n"
      "<text x=\"" + Fixed(kMargin) + "\" y=\"46\" fill=\"#444444\">Seen from above the first camera: its x to the "
      "right, its z (viewing direction) up the page.</text>\n"
      "<text x=\"" + Fixed(kMargin) + "\" y=\"64\" fill=\"#444444\">" + Escape(legend) + "</text>\n";
  svg = head + svg;
  svg += "<line x1=\"" + Fixed(bar_x) + "\" y1=\"" + Fixed(bar_y) + "\" x2=\"" + Fixed(bar_x + bar * scale) +
         "\" y2=\"" + Fixed(bar_y) + "\" stroke=\"black\" stroke-width=\"3\"/>\n";
  svg += "<text x=\"" + Fixed(bar_x + bar * scale + 8) + "\" y=\"" + Fixed(bar_y + 5) + "\">" + bar_text + "</text>\n";
  svg += "</svg>\n";
  return svg;
}

}  // namespace rigsim
