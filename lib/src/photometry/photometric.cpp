// The photometric correction of remapped samples (photometric.hpp).
#include "photometry/photometric.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/parallel.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

PhotometricStep::PhotometricStep(const Photometry& photometry, const PhotometricOutput& output,
                                 Size size, const std::string& what)
    : photometry_(photometry), output_(output), size_(size) {
  const Photometry& p = photometry_;
  for (const auto& [name, v] : {std::pair{"Er", p.red}, std::pair{"Eb", p.blue}})
    if (!(std::isfinite(v) && v > 0))
      throw Error(what + ": white balance " + name + number(v) +
                  ": expected a positive multiplier");
  if (!std::isfinite(p.exposure) || !std::isfinite(output.exposure) ||
      std::fabs(p.exposure - output.exposure) > 128)
    throw Error(what + ": exposure values " + number(p.exposure) + " and " +
                number(output.exposure) + ": expected finite EVs at most 128 apart");
  gain_ = std::exp2(p.exposure - output.exposure);
  const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
  radius_scale_ = 1 / std::sqrt(w * w / 4 + h * h / 4);
  const Vignetting& v = p.vignetting;
  centre_x_ = (w - 1) / 2 + v.shift_x;
  centre_y_ = (h - 1) / 2 + v.shift_y;
  if (v.flat_field) {
    const Image& f = *v.flat_field;
    if (f.size() != size || f.channels() != 1 || f.type() != PixelType::F32)
      throw Error(what + ": a flat field of " + size_text(f.size()) + " x " +
                  std::to_string(f.channels()) + " for an image of " + size_text(size) +
                  ": expected one float channel of the image's size");
    double lo = INFINITY, hi = 0;
    for (int64_t y = 0; y < f.height(); ++y) {
      const auto* row = reinterpret_cast<const float*>(f.row(y));
      for (int64_t x = 0; x < f.width(); ++x) {
        const double s = row[x];
        if (!std::isfinite(s)) lo = -INFINITY;
        lo = std::min(lo, s), hi = std::max(hi, s);
      }
    }
    if (!(lo > 0) || !(lo >= kMinVignetting * hi))
      throw Error(what + ": the flat field's values run from " + number(lo) + " to " + number(hi) +
                  ": expected finite values above " + number(kMinVignetting) + " of its largest");
    flat_max_ = hi;
  } else if (!v.identity()) {
    for (double c : v.coefficients)
      if (!std::isfinite(c) || std::fabs(c) > 1e6)
        throw Error(what + ": vignetting coefficient " + number(c) + ": expected a finite number");
    if (!std::isfinite(v.shift_x) || !std::isfinite(v.shift_y) ||
        std::fabs(v.shift_x) > 4 * (w + h) || std::fabs(v.shift_y) > 4 * (w + h))
      throw Error(what + ": vignetting centre shift " + number(v.shift_x) + "," +
                  number(v.shift_y) + ": expected finite pixels near the image");
    // The polynomial over r^2 from the centre to the farthest corner.
    double far = 0;
    for (double cx : {0.0, w - 1})
      for (double cy : {0.0, h - 1})
        far = std::max(far, std::hypot(cx - centre_x_, cy - centre_y_) * radius_scale_);
    const double near = std::hypot(std::clamp(centre_x_, 0.0, w - 1) - centre_x_,
                                   std::clamp(centre_y_, 0.0, h - 1) - centre_y_) *
                        radius_scale_;
    constexpr int kSteps = 8192;
    for (int k = 0; k <= kSteps; ++k) {
      const double r = near + (far - near) * k / kSteps, s = r * r;
      const auto& c = v.coefficients;
      const double value = c[0] + s * (c[1] + s * (c[2] + s * c[3]));
      if (!(value > kMinVignetting))
        throw Error(what + ": vignetting Va" + number(c[0]) + " Vb" + number(c[1]) + " Vc" +
                    number(c[2]) + " Vd" + number(c[3]) + " falls to " + number(value) +
                    " at radius " + number(r) +
                    " of the half diagonal, inside the image: nothing can be divided by it");
    }
  }
  identity_ = p.response == output.response && gain_ == 1 && p.red == 1 && p.blue == 1 &&
              v.identity() && !output.hdr;
}

double PhotometricStep::vignetting(double x, double y) const {
  const Vignetting& v = photometry_.vignetting;
  if (v.flat_field) {
    const Image& f = *v.flat_field;
    const auto ix =
        static_cast<int64_t>(std::clamp(std::round(x), 0.0, static_cast<double>(f.width() - 1)));
    const auto iy =
        static_cast<int64_t>(std::clamp(std::round(y), 0.0, static_cast<double>(f.height() - 1)));
    return reinterpret_cast<const float*>(f.row(iy))[ix] / flat_max_;
  }
  const double dx = (x - centre_x_) * radius_scale_, dy = (y - centre_y_) * radius_scale_;
  const double s = dx * dx + dy * dy;
  const auto& c = v.coefficients;
  return c[0] + s * (c[1] + s * (c[2] + s * c[3]));
}

void PhotometricStep::apply(Image& part, const Image* positions, double scale_x, double scale_y,
                            Image* weights, int threads) const {
  if (part.type() != PixelType::F32) throw Error("photometry: float samples expected");
  const int ch = part.channels();
  const int colours = ch - 1;
  if (weights) *weights = Image(part.size(), 1, PixelType::U8);
  const bool at_positions = needs_positions() && positions;
  const double wb[3] = {1 / photometry_.red, 1.0, 1 / photometry_.blue};
  parallel_rows(part.height(), threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      auto* row = reinterpret_cast<float*>(part.row(y));
      const float* at = at_positions ? reinterpret_cast<const float*>(positions->row(y)) : nullptr;
      unsigned char* weight = weights ? weights->row(y) : nullptr;
      for (int64_t x = 0; x < part.width(); ++x) {
        float* px = row + x * ch;
        if (!(px[ch - 1] > 0)) continue;
        if (weight) {
          float top = px[0];
          for (int c = 1; c < colours; ++c) top = std::max(top, px[c]);
          weight[x] = static_cast<unsigned char>(std::clamp(std::round(top * 255.0), 0.0, 255.0));
        }
        if (identity_) {
          for (int c = 0; c < colours; ++c) px[c] = std::clamp(px[c], 0.0f, 1.0f);
          continue;
        }
        double gain = gain_;
        if (at_positions) {
          const double sx = at[2 * x], sy = at[2 * x + 1];
          if (std::isfinite(sx) && std::isfinite(sy))
            gain /= vignetting(sx / scale_x - 0.5, sy / scale_y - 0.5);
        }
        for (int c = 0; c < colours; ++c) {
          double l = photometry_.response.irradiance(px[c]) * gain;
          if (colours == 3) l *= wb[c];
          const double out = output_.hdr ? l : output_.response.code(l);
          px[c] = static_cast<float>(out > 0 ? out : 0.0);
        }
      }
    }
  });
}

}  // namespace panoproj
