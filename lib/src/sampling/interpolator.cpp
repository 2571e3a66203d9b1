#include "sampling/interpolator.hpp"

#include <cmath>
#include <string>

#include "base/text.hpp"
#include "panoproj/conventions.hpp"
#include "panoproj/error.hpp"

namespace panoproj {

int support(Interp k) {
  switch (kernel_of(k)) {
    case Interp::Nearest: return 1;
    case Interp::Bilinear: return 2;
    case Interp::Bicubic: return 4;
    case Interp::Lanczos3: return 6;
    default: break;
  }
  return 1;
}

const char* name_of(Interp k) {
  switch (k) {
    case Interp::Nearest: return "nearest";
    case Interp::Bilinear: return "bilinear";
    case Interp::Bicubic: return "bicubic";
    case Interp::Lanczos3: return "lanczos3";
    case Interp::BicubicDering: return "bicubic-dering";
    case Interp::Lanczos3Dering: return "lanczos3-dering";
  }
  return "?";
}

Interp parse_interp(std::string_view name) {
  std::vector<std::string> names;
  for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3,
                   Interp::BicubicDering, Interp::Lanczos3Dering}) {
    if (name == name_of(k)) return k;
    names.emplace_back(name_of(k));
  }
  const std::string near = closest(name, names);
  throw Error("interpolator '" + std::string(name) + "' is unknown (" +
              (near.empty() ? "" : "did you mean " + near + "? ") +
              "expected nearest, bilinear, bicubic, lanczos3, bicubic-dering or lanczos3-dering)");
}

int64_t first_tap(Interp k, double s) {
  if (k == Interp::Nearest) return static_cast<int64_t>(std::floor(s));
  // Taps centred on the two pixel centres around s, widened by support/2 - 1 on each side.
  return static_cast<int64_t>(std::floor(s - 0.5)) - (support(k) / 2 - 1);
}

namespace {
// Keys (1981) cubic convolution kernel, a = -0.5.
double keys(double t) {
  constexpr double a = -0.5;
  t = std::fabs(t);
  if (t <= 1.0) return ((a + 2.0) * t - (a + 3.0)) * t * t + 1.0;
  if (t < 2.0) return ((a * t - 5.0 * a) * t + 8.0 * a) * t - 4.0 * a;
  return 0.0;
}
double lanczos3(double t) {
  if (std::fabs(t) >= 3.0) return 0.0;
  return sinc(kPi * t) * sinc(kPi * t / 3.0);
}
}  // namespace

void tap_weights(Interp k, double s, double* w) {
  const double f = (s - 0.5) - std::floor(s - 0.5);  // offset from the left centre, [0, 1)
  switch (kernel_of(k)) {
    case Interp::Nearest: w[0] = 1.0; return;
    case Interp::Bilinear:
      w[0] = 1.0 - f;
      w[1] = f;
      return;
    case Interp::Bicubic:
      for (int i = 0; i < 4; ++i) w[i] = keys(f - (i - 1));
      return;
    case Interp::Lanczos3: {
      double sum = 0.0;
      for (int i = 0; i < 6; ++i) sum += (w[i] = lanczos3(f - (i - 2)));
      for (int i = 0; i < 6; ++i) w[i] /= sum;
      return;
    }
    default: return;
  }
}

}  // namespace panoproj
