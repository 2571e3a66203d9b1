#pragma once
// One image's photometric model and its correction of remapped samples, as Hugin's nona applies
// it (photometric/ResponseTransform.h's InvResponseTransform): a sample's code value c (the
// source's code values interpolated, 0..1) becomes the linear
//   L = R_src^-1(c) * 2^(Eev - E) / V(x, y),  red / Er, blue / Eb (colour images),
// then R_out(L) for an LDR output (clamped to 0..1 by R_out's table) or L itself for HDR;
// negatives become 0. (x, y): the sample's source position. V: the vignetting,
//   a + b r^2 + c r^4 + d r^6,  r = |(x, y) - centre| / half diagonal,
// centre ((w - 1) / 2 + Vx, (h - 1) / 2 + Vy) in Hugin's pixels (centres at integers); or a flat
// field's value at the nearest pixel, the field scaled to a maximum of 1.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "panoproj/image.hpp"
#include "photometry/response.hpp"

namespace panoproj {

struct Vignetting {
  std::array<double, 4> coefficients{1, 0, 0, 0};  // a b c d
  double shift_x = 0, shift_y = 0;                 // Vx Vy (pixels)
  std::shared_ptr<const Image> flat_field;  // 1-channel float, linear, the image's size: used
                                            // in place of the polynomial
  bool identity() const { return !flat_field && coefficients == std::array<double, 4>{1, 0, 0, 0}; }
};

struct Photometry {
  Response response;         // the camera's
  double exposure = 0;       // Eev: the image's exposure value
  double red = 1, blue = 1;  // Er Eb: white balance multipliers
  Vignetting vignetting;
};

struct PhotometricOutput {
  bool hdr = false;     // linear output (a project's R1) instead of R_out's codes
  double exposure = 0;  // E: the output's exposure value
  Response response;    // R_out (LDR)
};

// A flat-field image (any channels and samples) as Vignetting::flat_field takes it: one float
// channel, the mean of its colours (alpha left out).
std::shared_ptr<const Image> flat_field_of(const Image& file);

// The correction of one image's samples; the constructor checks the model over the image of
// `size` (throws Error naming `what`: white balance outside 0.001..1000, exposures over 64 EV
// apart, vignetting at or below
// kMinVignetting anywhere in the image, a flat field of another size or not positive).
inline constexpr double kMinVignetting = 1e-3;
class PhotometricStep {
 public:
  PhotometricStep(const Photometry& photometry, const PhotometricOutput& output, Size size,
                  const std::string& what);
  // Whether a sample's value is kept (within 0..1); positions not needed.
  bool identity() const { return identity_; }
  bool needs_positions() const { return !photometry_.vignetting.identity(); }
  // A part's pixel (its centre's coordinates in the part) to its source position in Hugin's
  // pixels (centres at integers) of the model's image; false where it has none.
  using SourcePosition = std::function<bool(double x, double y, double& sx, double& sy)>;
  // part: float, its alpha last (gray + alpha or RGB + alpha); pixels of alpha 0 are left as they
  // are. position: where needs_positions() (else unused). V is taken at the positions of a grid
  // every kPositionStep pixels and interpolated bilinearly in the cells where that puts their
  // centre within 1e-5 (relative) of V at its own position, else (and for a flat field) taken
  // at each pixel's own.
  // weights: if given, nona's HDR weights (1 channel, 8-bit: the largest code value of each kept
  // pixel, 0..255).
  static constexpr int64_t kPositionStep = 8;
  void apply(Image& part, const SourcePosition& position, Image* weights, int threads) const;
  // V at Hugin's pixel (x, y). (Inline: once per corrected source pixel.)
  double vignetting(double x, double y) const {
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
  // One sample's code value c corrected: colour channel `channel` of an RGB pixel (0 red, 2
  // blue), or -1 (gray: no white balance); v: V at its position (1 without vignetting).
  double corrected(double c, int channel, double v) const {
    return from_irradiance(photometry_.response.irradiance(c), channel, v);
  }
  // The same from the code's irradiance R_src^-1(c) (tabulated by callers of integer samples).
  double irradiance(double c) const { return photometry_.response.irradiance(c); }
  double from_irradiance(double e, int channel, double v) const {
    return output(e * factor(channel, v));
  }
  // Its steps: the irradiance's factor (exposure, vignetting v, white balance), and the output
  // of a linear value.
  double factor(int channel, double v) const {
    double f = gain_ / v;
    if (channel == 0) f /= photometry_.red;
    if (channel == 2) f /= photometry_.blue;
    return f;
  }
  double output(double l) const {
    const double out = output_.hdr ? l : output_.response.code(l);
    return out > 0 ? out : 0.0;
  }

 private:
  Photometry photometry_;
  PhotometricOutput output_;
  Size size_;
  double gain_ = 1, radius_scale_ = 1, centre_x_ = 0, centre_y_ = 0, flat_max_ = 1;
  bool identity_ = false;
};

}  // namespace panoproj
