#include "apps/rigsim/render_support.h"

#include <chrono>
#include <cstdio>

#include "apps/rigsim/interrupt.h"
#include "apps/rigsim/progress.h"
#include "apps/rigsim/report_table.h"
#include "dataset/dataset.h"
#include "scenes/gltf_loader.h"

namespace rigsim::cli {

RenderOptions RenderSettings::ToRenderOptions() const {
  RenderOptions o;
  o.samples_per_pixel = samples_per_pixel;
  o.seed = seed;
  o.num_threads = threads;
  o.Check();
  return o;
}

void AddRenderSettingsOptions(CLI::App& cmd, RenderSettings& s) {
  cmd.add_option("--spp", s.samples_per_pixel, "RGB samples per pixel (anti-aliasing); labels and depth use the pixel centre")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd.add_option("--seed", s.seed, "seed of the sample jitter; the same seed gives the same bytes")
      ->capture_default_str();
  cmd.add_option("--threads", s.threads, "worker threads, 0 = all cores (output does not depend on it)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
}

Scene LoadSceneVerbose(const std::filesystem::path& path) {
  Scene scene = LoadGltf(path);
  std::fprintf(stderr, "scene %s: %zu meshes, %zu triangles, %zu textures\n", path.string().c_str(),
               scene.meshes.size(), scene.NumTriangles(), scene.textures.size());
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "  warning: %s\n", w.c_str());
  return scene;
}

void RenderAndReport(const RenderJob& job, const std::filesystem::path& out, bool force) {
  const auto start = std::chrono::steady_clock::now();
  Progress progress("rendering views");
  {
    // Ctrl-C stops after the view being rendered; the staging folder is removed on the way out.
    const InterruptScope interrupt;
    RenderDataset(job, out, force, [&](int done, int total) {
      progress(done, total);
      InterruptScope::ThrowIfRequested();
    });
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const size_t views = job.rig.cameras.size() * job.frames.frames.size();
  std::printf("rendered %zu views (%zu cameras x %zu frames, %d spp) into %s in %.1f s\n", views,
              job.rig.cameras.size(), job.frames.frames.size(), job.options.samples_per_pixel, out.string().c_str(),
              seconds);
  const OverlapTable overlap = ReadOverlap(DatasetLayout(out).OverlapJson());
  std::printf("ground-truth overlap (fraction of the view both cameras share):\n");
  for (size_t a = 0; a < job.rig.cameras.size(); ++a) {
    for (size_t b = a + 1; b < job.rig.cameras.size(); ++b) {
      const auto it = overlap.find({job.rig.cameras[a].name, job.rig.cameras[b].name});
      if (it != overlap.end()) {
        std::printf("  %s-%s %5.1f%%\n", job.rig.cameras[a].name.c_str(), job.rig.cameras[b].name.c_str(),
                    100 * it->second);
      }
    }
  }
}

}  // namespace rigsim::cli
