// The chart of an error-against-time sweep (accuracy.hpp): lines and boxes drawn here, the labels
// by OpenImageIO's text rendering (the plugin, loaded for the plot).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "panoproj/diagnostics/accuracy.hpp"
#include "panoproj/io.hpp"
#include "io/oiio_plugin.hpp"

namespace panoproj {
namespace {

// One colour per kernel, in interpolator order.
constexpr float kColours[4][3] = {{0.55f, 0.55f, 0.55f}, {0.12f, 0.47f, 0.71f}, {0.17f, 0.63f, 0.17f}, {0.84f, 0.15f, 0.16f}};

// A float RGB canvas with OpenImageIO's drawing calls' conventions (inclusive corners).
class Canvas {
 public:
  Canvas(int w, int h, const float* colour) : image_({w, h}, 3, PixelType::F32) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) put(x, y, colour);
  }
  void line(int x0, int y0, int x1, int y1, const float* c) {  // Bresenham
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    for (int err = dx + dy;;) {
      put(x0, y0, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
  }
  void box(int x0, int y0, int x1, int y1, const float* c, bool fill = false) {
    if (!fill) {
      line(x0, y0, x1, y0, c), line(x1, y0, x1, y1, c), line(x1, y1, x0, y1, c), line(x0, y1, x0, y0, c);
      return;
    }
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) put(x, y, c);
  }
  void text(OiioBackend& oiio, int x, int y, const std::string& s, const float* c, int size) {
    oiio.draw_text(image_, x, y, s, size, c);
  }
  Image bytes() const { return convert_pixels(image_, PixelType::U8); }

 private:
  void put(int x, int y, const float* c) {
    if (x < 0 || y < 0 || x >= image_.width() || y >= image_.height()) return;
    std::memcpy(image_.pixel(x, y), c, 3 * sizeof(float));
  }
  Image image_;
};

}  // namespace

Image plot_sweep(const std::vector<SweepResult>& results, const std::string& title) {
  constexpr int W = 960, H = 640, left = 80, right = 250, top = 50, bottom = 60;
  const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, grey[3] = {0.85f, 0.85f, 0.85f}, front_c[3] = {0.9f, 0.5f, 0.0f};
  OiioBackend& oiio = oiio_backend("labelling the plot");
  Canvas buf(W, H, white);
  // Axes: time on a log scale, PSNR linear, both padded.
  double t0 = HUGE_VAL, t1 = 0, p0 = HUGE_VAL, p1 = -HUGE_VAL;
  for (const auto& r : results)
    t0 = std::min(t0, r.median_ms), t1 = std::max(t1, r.median_ms), p0 = std::min(p0, r.error.psnr), p1 = std::max(p1, r.error.psnr);
  const double lt0 = std::floor(std::log10(t0 / 1.2)), lt1 = std::ceil(std::log10(t1 * 1.2));
  p0 = std::floor(p0 - 1), p1 = std::ceil(p1 + 1);
  auto X = [&](double ms) { return left + static_cast<int>((std::log10(ms) - lt0) / (lt1 - lt0) * (W - left - right)); };
  auto Y = [&](double db) { return H - bottom - static_cast<int>((db - p0) / (p1 - p0) * (H - top - bottom)); };
  auto text = [&](int x, int y, const std::string& s, const float* c, int size = 14) {
    buf.text(oiio, x, y, s, c, size);  // no font: no text
  };
  for (double d = lt0; d <= lt1 + 1e-9; ++d)
    for (double m : {1.0, 2.0, 5.0}) {
      const double ms = std::pow(10.0, d) * m;
      if (std::log10(ms) > lt1 + 1e-9) break;
      buf.line(X(ms), top, X(ms), H - bottom, grey);
      char s[32];
      std::snprintf(s, sizeof s, "%g", ms);
      text(X(ms) - 8, H - bottom + 20, s, black);
    }
  const double step = p1 - p0 > 20 ? 5 : 2;
  for (double db = std::ceil(p0 / step) * step; db <= p1; db += step) {
    buf.line(left, Y(db), W - right, Y(db), grey);
    text(left - 40, Y(db) + 5, std::to_string(static_cast<int>(db)), black);
  }
  buf.box(left, top, W - right, H - bottom, black);
  text(left + (W - left - right) / 2 - 70, H - 15, "median time (ms, log)", black);
  text(10, top - 15, "PSNR (dB)", black);
  text(left, 25, title, black, 16);
  // The Pareto front, then the points: a filled square (off), a ring (auto), a triangle (mip),
  // a cross (N x N), a diamond of lines (the reference engine).
  const auto front = pareto_front(results);
  for (size_t i = 1; i < front.size(); ++i)
    buf.line(X(results[front[i - 1]].median_ms), Y(results[front[i - 1]].error.psnr),
                                    X(results[front[i]].median_ms), Y(results[front[i]].error.psnr), front_c);
  for (const auto& r : results) {
    const float* c = kColours[static_cast<int>(r.option.interp)];
    const int x = X(r.median_ms), y = Y(r.error.psnr);
    if (r.option.engine == Engine::Reference) {
      buf.line(x - 6, y, x, y - 6, c), buf.line(x, y - 6, x + 6, y, c);
      buf.line(x + 6, y, x, y + 6, c), buf.line(x, y + 6, x - 6, y, c);
    } else if (r.option.antialias.mode == Antialias::Mode::Off) {
      buf.box(x - 4, y - 4, x + 4, y + 4, c, true);
    } else if (r.option.antialias.mode == Antialias::Mode::Auto) {
      buf.box(x - 5, y - 5, x + 5, y + 5, c), buf.box(x - 4, y - 4, x + 4, y + 4, c);
    } else if (r.option.antialias.mode == Antialias::Mode::Mip) {
      buf.line(x - 6, y + 5, x + 6, y + 5, c), buf.line(x - 6, y + 5, x, y - 6, c);
      buf.line(x, y - 6, x + 6, y + 5, c);
    } else {
      buf.line(x - 5, y - 5, x + 5, y + 5, c), buf.line(x - 5, y + 5, x + 5, y - 5, c);
    }
  }
  // Legend.
  const int lx = W - right + 20;
  int ly = top + 10;
  for (Interp k : {Interp::Nearest, Interp::Bilinear, Interp::Bicubic, Interp::Lanczos3}) {
    buf.box(lx, ly - 8, lx + 8, ly, kColours[static_cast<int>(k)], true);
    text(lx + 16, ly, name_of(k), black);
    ly += 22;
  }
  ly += 10;
  for (const char* s : {"filled square: antialias off", "ring: antialias auto", "triangle: mip levels",
                        "cross: N x N sub-pixels",
                        "diamond: reference engine", "orange line: Pareto front"})
    text(lx, ly, s, black, 12), ly += 20;
  return buf.bytes();
}

}  // namespace panoproj
