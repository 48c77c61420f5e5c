// Defocus from a thin lens, applied to rendered RGB in linear light (labels, instances and depth
// stay exact ground truth). Off unless an f-number is given: a pinhole has no defocus.
//
// Thin lens with focal length f, f-number N, focused at distance s: a point at distance d is
// imaged as a blur circle of diameter
//   c = f^2 / (N (s - f)) * |d - s| / d            (metres on the sensor)
//   c_px = c / pixel_pitch = fx * (f / N) / (s - f) * |d - s| / d
// with f = fx * pixel_pitch (fx: the camera's focal length in pixels). d is the point's distance
// along the optical axis (AxialDistance: the depth image's range times its ray's z), so the surface
// in focus is the plane at s, as a thin lens has it; beyond 90 deg off axis (a fisheye's rim) the
// thin lens means nothing and d is the range. Pixels without a surface (sky) are at infinity:
// c_px = fx (f / N) / (s - f).
//
// The blur: every pixel q spreads its value uniformly over a disc of radius r_q = c_px / 2 (edges
// anti-aliased over one pixel; radii clipped to max_radius_px), computed as a gather: output pixel p
// is the weighted mean of the q whose disc covers it, each weighted by its coverage of p divided by
// its disc's area. Depth test: a q behind p (larger distance) spreads over p with at most p's own
// radius, so an in-focus foreground keeps a sharp edge against a blurred background, while a
// blurred foreground still spreads over what is behind it (as its out-of-focus rim does in a real
// lens; the background it hides is not recovered). Blur circles under one pixel across change
// nothing. Pixels outside the lens's valid region neither give nor receive light.
#pragma once

#include "geometry/image.h"
#include "renderer/camera_rays.h"

namespace rigsim {

struct DefocusOptions {
  double f_number = 0.0;          // N; 0 = a pinhole: no defocus
  double focus_distance_m = 0.0;  // s: the distance in sharp focus (metres)
  double pixel_pitch_um = 3.0;    // the sensor's pixel size (micrometres): f = fx * pixel_pitch
  double max_radius_px = 16.0;    // blur circles are clipped to this radius (the cost grows with its square)

  bool enabled() const { return f_number > 0.0; }
  // Throws std::invalid_argument naming the field: f-number in [0.5, 64] when not 0, focus
  // distance > 0 when enabled, pixel pitch in (0, 100] um, max radius in [1, 64] px.
  void Check() const;
};

// Each pixel's distance along the optical axis from its `range` (the depth image: metres along the
// pixel centre's ray, 0 = no surface): range times the z of the ray's unit bearing (`rays`, the
// camera's, PixelCentreRayCache); where that z is not positive, the range. Same size as `range`.
ImageF AxialDistance(const PixelCentreRays& rays, const ImageF& range);

// The blur circle's diameter in pixels for a point at axial distance `distance_m` (0 or infinite: no
// surface, at infinity) seen by a camera of focal length `fx_px`. Throws std::invalid_argument when
// the focus distance is not beyond the focal length.
double BlurCircleDiameterPx(const DefocusOptions& options, double fx_px, double distance_m);

// Blurs `linear` (3 channels, linear light) in place by each pixel's blur circle from `distance`
// (AxialDistance; 1 channel, same size; 0 = no surface). `invalid` (optional, 1 channel): pixels outside the
// lens's valid region. `num_threads`: 0 = all cores; the result does not depend on it. Does nothing
// when the options are off. Throws std::invalid_argument on a size mismatch or bad options.
void ApplyDefocus(const DefocusOptions& options, double fx_px, const ImageF& distance, ImageF& linear,
                  const ImageU8* invalid = nullptr, int num_threads = 0);

}  // namespace rigsim
