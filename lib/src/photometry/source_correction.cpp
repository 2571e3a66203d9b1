// A source frame's photometric correction (source_correction.hpp).
#include "photometry/source_correction.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <string_view>

#include "base/parallel.hpp"
#include "base/sample_io.hpp"
#include "geometry/sampling_facts.hpp"
#include "panoproj/error.hpp"
#include "spec/photometric_keys.hpp"

namespace panoproj {

Photometry lens_photometry(const ProjectionSpec& spec, int lens, bool float_samples,
                           const std::string& what) {
  const PhotometricKeys k = photometric_keys(spec, lens);
  Photometry p;
  if (!k.linear.value_or(float_samples))
    p.response = Response::emor(k.emor.value_or(std::array<double, 5>{}), what + ": response");
  p.exposure = k.ev;
  p.red = k.red, p.blue = k.blue;
  p.vignetting.coefficients = k.vignetting;
  p.vignetting.shift_x = k.shift_x, p.vignetting.shift_y = k.shift_y;
  return p;
}

std::shared_ptr<const SourceCorrection> SourceCorrection::make(const ProjectionSpec& from,
                                                               const ProjectionSpec& to,
                                                               const Projection& source,
                                                               StereoLayout stereo) {
  if (!gives_photometry(from) && !gives_photometry(to)) return nullptr;
  for (const ParamDef& d : photometric_key_defs(true))
    if (std::string_view(d.key) != "ev" && to.given(d.key))
      throw Error("to: " + to.str() + ": " + d.key +
                  "= describes a source's lens (a target takes ev=, the output's exposure)");
  // (The module's facts say what lenses a frame holds: sampling_facts.hpp.)
  const SamplingFacts facts = sampling_facts(source);
  if (facts.max)
    for (const char* k : {"vignetting", "vignetting_centre", "vignetting2", "vignetting_centre2"})
      if (from.given(k))
        throw Error("from: " + from.str() + ": " + k +
                    "= on a GoPro MAX frame (its cells are cube faces the camera made, no lens's "
                    "image; give ev= and wb= per lens)");
  std::shared_ptr<SourceCorrection> c(new SourceCorrection(source, stereo));
  c->max_ = sampling_facts(c->source_).max;  // (into its own copy of the projection)
  const Size eye = size_of(source);
  std::vector<PixelRect> rects{{0, 0, eye.width, eye.height}};
  if (const DualFisheye* d = facts.dual) {
    const int64_t w = d->cell_width(), h = d->cell_height();
    rects = {{0, 0, w, h},
             w == eye.width ? PixelRect{0, h, eye.width, eye.height}
                            : PixelRect{w, 0, eye.width, eye.height}};
  } else if (facts.max) {
    rects.push_back(rects[0]);
  }
  // The output: lens 0's response at the target's exposure, else the lenses' mean.
  double mean = 0;
  for (size_t k = 0; k < rects.size(); ++k)
    mean += photometric_keys(from, static_cast<int>(k)).ev / static_cast<double>(rects.size());
  std::array<PhotometricOutput, 2> outputs;  // for integer and float samples
  for (const bool f : {false, true}) {
    outputs[f].exposure = to.given("ev") ? *to.number("ev") : mean;
    outputs[f].response = lens_photometry(from, 0, f, "from: " + from.str()).response;
  }
  for (size_t k = 0; k < rects.size(); ++k) {
    Lens lens;
    lens.rect = rects[k];
    const std::string what =
        "from: " + from.str() + (rects.size() > 1 ? " lens " + std::to_string(k) : "");
    for (const bool f : {false, true})
      (f ? lens.floating : lens.integer)
          .emplace(lens_photometry(from, static_cast<int>(k), f, what), outputs[f], rects[k].size(),
                   what);
    c->lenses_.push_back(std::move(lens));
  }
  return c;
}

bool SourceCorrection::identity(PixelType type) const {
  for (const Lens& l : lenses_)
    if (!l.step(type).identity()) return false;
  return true;
}

int SourceCorrection::lens_at(double x, double y) const {
  if (max_) return max_->lens_at(x, y);
  for (size_t k = 1; k < lenses_.size(); ++k) {
    const PixelRect& r = lenses_[k].rect;
    if (x >= static_cast<double>(r.x0) && y >= static_cast<double>(r.y0))
      return static_cast<int>(k);
  }
  return 0;
}

void SourceCorrection::apply(const Image& src, Image& out, int threads) const {
  out = Image(src.size(), src.channels(), src.type(), src.alpha_channel(), Image::Unfilled{});
  out.set_window(src.origin_x(), src.origin_y(), src.frame_size());
  const Size eye = size_of(source_), full = stereo_frame(eye, stereo_);
  const double sx = static_cast<double>(full.width) / static_cast<double>(src.frame_size().width);
  const double sy = static_cast<double>(full.height) / static_cast<double>(src.frame_size().height);
  const int alpha = src.alpha_channel();
  const int colours = src.channels() - (alpha >= 0 ? 1 : 0);
  const PixelType type = src.type();
  with_sample_type(type, [&](auto t) {
    using T = decltype(t);
    const double unit = unit_of(type);
    // Integer codes' irradiances, per lens.
    std::vector<std::vector<double>> tables(lenses_.size());
    if constexpr (std::is_integral_v<T>)
      for (size_t k = 0; k < lenses_.size(); ++k) {
        tables[k].resize(static_cast<size_t>(unit) + 1);
        for (size_t c = 0; c < tables[k].size(); ++c)
          tables[k][c] = lenses_[k].step(type).irradiance(static_cast<double>(c) / unit);
      }
    // Each lens's factor per colour without vignetting (exposure over white balance; 1: gray).
    std::vector<std::array<double, 3>> gains(lenses_.size());
    for (size_t k = 0; k < lenses_.size(); ++k)
      for (int c = 0; c < 3; ++c)
        gains[k][static_cast<size_t>(c)] = lenses_[k].step(type).factor(c, 1);
    parallel_rows(src.height(), threads, [&](int64_t y0, int64_t y1) {
      for (int64_t y = y0; y < y1; ++y) {
        const unsigned char* in = src.row(y);
        unsigned char* o = out.row(y);
        for (int64_t x = 0; x < src.width(); ++x) {
          // The pixel's centre in the full frame, then in its eye's.
          double fx = (static_cast<double>(src.origin_x() + x) + 0.5) * sx;
          double fy = (static_cast<double>(src.origin_y() + y) + 0.5) * sy;
          if (stereo_ == StereoLayout::TopBottom && fy >= static_cast<double>(eye.height))
            fy -= static_cast<double>(eye.height);
          if (stereo_ == StereoLayout::SideBySide && fx >= static_cast<double>(eye.width))
            fx -= static_cast<double>(eye.width);
          const size_t k = static_cast<size_t>(lens_at(fx, fy));
          const Lens& lens = lenses_[k];
          const PhotometricStep& step = lens.step(type);
          const size_t bytes = static_cast<size_t>(src.channels()) * sizeof(T);
          const unsigned char* p = in + static_cast<size_t>(x) * bytes;
          unsigned char* q = o + static_cast<size_t>(x) * bytes;
          if (step.identity()) {
            std::memcpy(q, p, bytes);
            continue;
          }
          // (Hugin's pixels in the lens image: centres at integers.)
          const double v = step.needs_positions()
                               ? step.vignetting(fx - static_cast<double>(lens.rect.x0) - 0.5,
                                                 fy - static_cast<double>(lens.rect.y0) - 0.5)
                               : 1.0;
          const double inverse_v = 1 / v;
          int colour = 0;
          for (int c = 0; c < src.channels(); ++c) {
            const size_t at = static_cast<size_t>(c) * sizeof(T);
            if (c == alpha) {
              std::memcpy(q + at, p + at, sizeof(T));
              continue;
            }
            const double f = gains[k][colours == 3 ? static_cast<size_t>(colour) : 1] * inverse_v;
            ++colour;
            if constexpr (std::is_integral_v<T>) {
              // (Non-negative: rounded half up, as store's nearest for all but exact halves.)
              T code;
              std::memcpy(&code, p + at, sizeof(T));
              const double out = step.output(tables[k][code] * f) * unit + 0.5;
              const T t = static_cast<T>(out < unit ? out : unit);
              std::memcpy(q + at, &t, sizeof(T));
            } else {
              store<T>(q + at, step.output(step.irradiance(load<T>(p + at)) * f));
            }
          }
        }
      }
    });
  });
}

}  // namespace panoproj
