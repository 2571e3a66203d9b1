// Fuzzes the Hugin project reader (jobs/stitch/pto_project.hpp) and what reads its values: the
// panorama's and images' specs, their projections, each image's extent on the canvas and its
// photometric correction (finite, non-negative samples from any it accepts). Only
// panoproj::Error may leave it; whatever it accepts must hold what the reader promises.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "jobs/stitch/layer_masks.hpp"
#include "jobs/stitch/pano_spec.hpp"
#include "jobs/stitch/pto_photometry.hpp"
#include "jobs/stitch/pto_project.hpp"
#include "jobs/stitch/stitch.hpp"
#include "panoproj/error.hpp"
#include "panoproj/projection.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace panoproj;
  try {
    const PtoProject p = parse_pto(std::string(reinterpret_cast<const char*>(data), size), "f.pto");
    if (p.images.empty() || !(p.pano.hfov > 0 && p.pano.hfov <= 360) || p.pano.width < 1)
      std::abort();
    for (const PtoImage& im : p.images)
      if (!(im.hfov > 0 && im.hfov <= 360) ||
          !std::isfinite(im.a + im.b + im.c + im.d + im.e + im.g + im.t) || im.lens < 0 ||
          im.lens >= static_cast<int>(p.images.size()) || im.stack < 0 ||
          (im.crop &&
           (im.crop->left < 0 || im.crop->right > im.width || im.crop->left >= im.crop->right)))
        std::abort();
    for (const PtoMask& m : p.masks)
      if (m.xy.size() < 6 || m.xy.size() % 2 || m.image >= static_cast<int>(p.images.size()))
        std::abort();
    // Small canvases only: the extent's miniature is at most 180 px a side whatever the canvas.
    StitchPlan plan;
    plan.project = p;
    plan.pano = parse_spec(pano_spec(p));
    plan.canvas = {p.pano.width, p.pano.height};
    make_projection(*plan.pano, plan.canvas);
    for (size_t i = 0; i < p.images.size() && i < 4; ++i) {
      const PtoImage& im = p.images[i];
      StitchLayer layer;
      layer.index = static_cast<int>(i);
      layer.lens = parse_spec(image_spec(p, im));
      layer.rotation = image_rotation(im);
      make_projection(*layer.lens, {im.width, im.height});
      const PixelRect r = layer_extent(plan, layer);
      if (r.width() < 0 || r.x0 < 0 || r.x1 > plan.canvas.width || r.y1 > plan.canvas.height)
        std::abort();
      pano_exclusions(p, static_cast<int>(i));
      image_masks(p, static_cast<int>(i));
      const PhotometricStep step(image_photometry(p, im), pano_output(p), {im.width, im.height},
                                 "f.pto");
      // Three samples (codes 0, 0.5, 1.25) at the image's corner, centre and far corner.
      Image part({3, 1}, 4, PixelType::F32, 3);
      auto* px = reinterpret_cast<float*>(part.row(0));
      const float codes[3] = {0.0f, 0.5f, 1.25f};
      for (int k = 0; k < 3; ++k) {
        std::fill(px + 4 * k, px + 4 * k + 4, codes[k]);
        px[4 * k + 3] = 1;
      }
      step.apply(
          part,
          [&](double x, double, double& sx, double& sy) {
            sx = static_cast<double>(im.width - 1) * (x - 0.5) / 2;
            sy = static_cast<double>(im.height - 1) * (x - 0.5) / 2;
            return true;
          },
          nullptr, 1);
      for (int k = 0; k < 12; ++k)
        if (!(px[k] >= 0) || !std::isfinite(px[k])) std::abort();
    }
  } catch (const Error&) {
  }
  return 0;
}
