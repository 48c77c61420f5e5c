// For benchmarks only (bench/render_bench.cc): the lower bound Renderer::Render is measured
// against, Embree alone tracing the rays Render traces.
#pragma once

#include <cstddef>

#include "geometry/camera.h"
#include "geometry/rigid3.h"
#include "renderer/renderer.h"

namespace rigsim {

// What TraceOnlyForBenchmark traced and how long Embree alone took.
struct TraceOnlyStats {
  double seconds = 0.0;       // wall time of the Embree calls only (rays prepared beforehand)
  size_t primary_rays = 0;    // camera rays: what Render traces for the same view
  size_t shadow_rays = 0;     // shadow rays: what Render casts for the same view
};

// Generates exactly the rays renderer.Render would trace for this view (pixel centres, the
// jittered samples when samples_per_pixel > 1, and the shadow rays of the shaded samples),
// untimed, then times Embree alone tracing them as Render does (the same coherent streams of a
// batch's camera rays, then its shadow rays, over the same tiles on options.num_threads threads):
// no ray generation, shading, texturing or output.
TraceOnlyStats TraceOnlyForBenchmark(const Renderer& renderer, const Camera& camera, const Rigid3d& cam_from_world,
                                     const RenderOptions& options);

// The floor under a labelled frame at 1 spp: the same pixel-centre rays from the cached bearings
// and the same tiles, batches and Embree streams as Render, label, instance and range written
// straight into the images, and a flat grey surface lit by a face-normal Lambert with the sun's
// shadow rays and the sky, sRGB-encoded: the four images allocated and filled with nothing Render
// could leave out (no textures, materials, vertex normals or tile buffers). Throws
// std::invalid_argument unless options.samples_per_pixel is 1.
RenderedView MinimalFrameForBenchmark(const Renderer& renderer, const Camera& camera, const Rigid3d& cam_from_world,
                                      const RenderOptions& options);

}  // namespace rigsim
