// The photometric correction of remapped samples (photometric.hpp).
#include "photometry/photometric.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/parallel.hpp"
#include "base/sample_io.hpp"
#include "base/text.hpp"
#include "panoproj/error.hpp"

namespace panoproj {
namespace {}  // namespace

std::shared_ptr<const Image> flat_field_of(const Image& file) {
  auto out = std::make_shared<Image>(file.size(), 1, PixelType::F32);
  const int alpha = file.alpha_channel();
  const int colours = file.channels() - (alpha >= 0 ? 1 : 0);
  with_sample_type(file.type(), [&](auto t) {
    using T = decltype(t);
    for (int64_t y = 0; y < file.height(); ++y) {
      auto* o = reinterpret_cast<float*>(out->row(y));
      for (int64_t x = 0; x < file.width(); ++x) {
        double sum = 0;
        for (int c = 0; c < file.channels(); ++c)
          if (c != alpha) sum += load<T>(file.pixel(x, y) + static_cast<size_t>(c) * sizeof(T));
        o[x] = static_cast<float>(sum / colours);
      }
    }
  });
  return out;
}

PhotometricStep::PhotometricStep(const Photometry& photometry, const PhotometricOutput& output,
                                 Size size, const std::string& what)
    : photometry_(photometry), output_(output), size_(size) {
  const Photometry& p = photometry_;
  for (const auto& [name, v] : {std::pair{"Er", p.red}, std::pair{"Eb", p.blue}})
    if (!(std::isfinite(v) && v > 0))
      throw Error(what + ": white balance " + name + number_text(v, 6) +
                  ": expected a positive multiplier");
  if (!std::isfinite(p.exposure) || !std::isfinite(output.exposure) ||
      std::fabs(p.exposure - output.exposure) > 64)
    throw Error(what + ": exposure values " + number_text(p.exposure, 6) + " and " +
                number_text(output.exposure, 6) + ": expected finite EVs at most 64 apart");
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
      throw Error(what + ": the flat field's values run from " + number_text(lo, 6) + " to " +
                  number_text(hi, 6) + ": expected finite values above " +
                  number_text(kMinVignetting, 6) + " of its largest");
    flat_max_ = hi;
  } else if (!v.identity()) {
    for (double c : v.coefficients)
      if (!std::isfinite(c) || std::fabs(c) > 1e6)
        throw Error(what + ": vignetting coefficient " + number_text(c, 6) +
                    ": expected a finite number");
    if (!std::isfinite(v.shift_x) || !std::isfinite(v.shift_y) ||
        std::fabs(v.shift_x) > 4 * (w + h) || std::fabs(v.shift_y) > 4 * (w + h))
      throw Error(what + ": vignetting centre shift " + number_text(v.shift_x, 6) + "," +
                  number_text(v.shift_y, 6) + ": expected finite pixels near the image");
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
        throw Error(what + ": vignetting Va" + number_text(c[0], 6) + " Vb" + number_text(c[1], 6) +
                    " Vc" + number_text(c[2], 6) + " Vd" + number_text(c[3], 6) + " falls to " +
                    number_text(value, 6) + " at radius " + number_text(r, 6) +
                    " of the half diagonal, inside the image: nothing can be divided by it");
    }
  }
  identity_ = p.response == output.response && gain_ == 1 && p.red == 1 && p.blue == 1 &&
              v.identity() && !output.hdr;
}

namespace {

// V at the nodes of a grid over a part: columns and rows every `step` pixels and the last. A
// cell is interpolated where V at its centre is within kTolerance (relative) of its nodes' mean
// (the bilinear error peaks there), else each of its pixels takes V at its own position.
struct VignettingGrid {
  static constexpr double kTolerance = 1e-5;
  std::vector<int64_t> xs, ys;
  std::vector<double> v;       // NaN: the node has no source
  std::vector<uint8_t> exact;  // per cell
  static std::vector<int64_t> nodes(int64_t n, int64_t step) {
    std::vector<int64_t> out;
    for (int64_t k = 0; k < n; k += step) out.push_back(k);
    if (out.back() != n - 1) out.push_back(n - 1);
    return out;
  }
  template <class At>
  void check_cells(const At& at, int64_t j0, int64_t j1) {
    const size_t w = xs.size();
    for (int64_t j = j0; j < j1; ++j)
      for (size_t i = 0; i + 1 < w; ++i) {
        const size_t k = static_cast<size_t>(j) * w + i;
        const double mean = (v[k] + v[k + 1] + v[k + w] + v[k + w + 1]) / 4;
        const double centre = at(
            static_cast<double>(xs[i] + xs[i + 1]) / 2,
            static_cast<double>(ys[static_cast<size_t>(j)] + ys[static_cast<size_t>(j) + 1]) / 2);
        exact[static_cast<size_t>(j) * (w - 1) + i] =
            !(std::isfinite(mean) && std::fabs(centre - mean) <= kTolerance * std::fabs(centre));
      }
  }
  // The interpolated V at pixel (x, y); NaN where its cell is exact.
  double at(int64_t x, int64_t y, int64_t step) const {
    const size_t i = std::min(static_cast<size_t>(x / step), xs.size() - 2);
    const size_t j = std::min(static_cast<size_t>(y / step), ys.size() - 2);
    if (exact[j * (xs.size() - 1) + i]) return NAN;
    const double tx = static_cast<double>(x - xs[i]) / static_cast<double>(xs[i + 1] - xs[i]);
    const double ty = static_cast<double>(y - ys[j]) / static_cast<double>(ys[j + 1] - ys[j]);
    const size_t w = xs.size(), k = j * w + i;
    return (1 - ty) * ((1 - tx) * v[k] + tx * v[k + 1]) +
           ty * ((1 - tx) * v[k + w] + tx * v[k + w + 1]);
  }
};

}  // namespace

void PhotometricStep::apply(Image& part, const SourcePosition& position, Image* weights,
                            int threads) const {
  if (part.type() != PixelType::F32) throw Error("photometry: float samples expected");
  const int ch = part.channels();
  const int colours = ch - 1;
  if (weights) *weights = Image(part.size(), 1, PixelType::U8);
  const bool vignetted = needs_positions() && position && !identity_;
  // V at a pixel's own position (its centre), NaN without one.
  const auto own = [&](double x, double y) {
    double sx, sy;
    return position(x + 0.5, y + 0.5, sx, sy) ? vignetting(sx, sy) : NAN;
  };
  // (A flat field is not smooth: each pixel takes its own.)
  VignettingGrid grid;
  if (vignetted && !photometry_.vignetting.flat_field && part.width() > 1 && part.height() > 1) {
    grid.xs = VignettingGrid::nodes(part.width(), kPositionStep);
    grid.ys = VignettingGrid::nodes(part.height(), kPositionStep);
    grid.v.resize(grid.xs.size() * grid.ys.size());
    grid.exact.resize((grid.xs.size() - 1) * (grid.ys.size() - 1));
    parallel_rows(static_cast<int64_t>(grid.ys.size()), threads, [&](int64_t j0, int64_t j1) {
      for (int64_t j = j0; j < j1; ++j)
        for (size_t i = 0; i < grid.xs.size(); ++i)
          grid.v[static_cast<size_t>(j) * grid.xs.size() + i] =
              own(static_cast<double>(grid.xs[i]),
                  static_cast<double>(grid.ys[static_cast<size_t>(j)]));
    });
    parallel_rows(static_cast<int64_t>(grid.ys.size()) - 1, threads,
                  [&](int64_t j0, int64_t j1) { grid.check_cells(own, j0, j1); });
  }
  parallel_rows(part.height(), threads, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y) {
      auto* row = reinterpret_cast<float*>(part.row(y));
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
        double v = 1;
        if (vignetted) {
          v = grid.v.empty() ? NAN : grid.at(x, y, kPositionStep);
          if (!std::isfinite(v)) v = own(static_cast<double>(x), static_cast<double>(y));
          if (!std::isfinite(v)) v = 1;
        }
        for (int c = 0; c < colours; ++c)
          px[c] = static_cast<float>(corrected(px[c], colours == 3 ? c : -1, v));
      }
    }
  });
}

}  // namespace panoproj
