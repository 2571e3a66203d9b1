#pragma once
// Cartographic plane <-> pixels: the box [xmin, xmax] x [ymin, ymax] fills the frame, north (+Y)
// up. The box is the map's outline's bounding box (aspect=stretch), or that box widened about its
// centre to the frame's aspect (aspect=keep: square pixels, the outline inscribed and centred). Longitudes are taken relative to the central meridian lon0.
// MapProjection<Derived> turns a map's plane equations, Derived::forward(lambda, phi, X, Y) and
// bool Derived::inverse(X, Y, lambda, phi) (false outside the outline) and a cheap
// bool Derived::inside(X, Y) (the same outline test without the inverse), into a projection.
#include "panoproj/conventions.hpp"
#include "panoproj/projections/frame.hpp"

namespace panoproj {

struct MapFrame {
  Size size;
  double xmin, xmax, ymin, ymax;

  double plane_x(double px) const {
    return xmin + px / static_cast<double>(size.width) * (xmax - xmin);
  }
  double plane_y(double py) const {
    return ymax - py / static_cast<double>(size.height) * (ymax - ymin);
  }
  double pixel_x(double X) const {
    return (X - xmin) / (xmax - xmin) * static_cast<double>(size.width);
  }
  double pixel_y(double Y) const {
    return (ymax - Y) / (ymax - ymin) * static_cast<double>(size.height);
  }
  // Pixels per plane unit horizontally (all forms here have unit scale at their centre).
  double density() const { return static_cast<double>(size.width) / (xmax - xmin); }

  // The box widened about its centre so that a pixel spans as much of X as of Y.
  void keep_square() {
    const double w = static_cast<double>(size.width), h = static_cast<double>(size.height);
    const double per_x = (xmax - xmin) / w, per_y = (ymax - ymin) / h;  // plane units per pixel
    if (per_x > per_y) {
      const double c = 0.5 * (ymin + ymax);
      ymin = c - 0.5 * per_x * h;
      ymax = c + 0.5 * per_x * h;
    } else if (per_y > per_x) {
      const double c = 0.5 * (xmin + xmax);
      xmin = c - 0.5 * per_y * w;
      xmax = c + 0.5 * per_y * w;
    }
  }
};

template <class Derived>
class MapProjection {
 public:
  bool to_ray(double x, double y, Ray& d) const {
    double lam, phi;
    if (!self().inverse(frame_.plane_x(x), frame_.plane_y(y), lam, phi)) return false;
    d = ray_from_lonlat(lam + lon0_, phi);
    return true;
  }
  bool to_pixel(const Ray& d, double& x, double& y) const {
    double X, Y;
    self().forward(wrap_pi(longitude(d) - lon0_), latitude(d), X, Y);
    x = frame_.pixel_x(X);
    y = frame_.pixel_y(Y);
    return in_frame(x, y, frame_.size);
  }

  // Whether pixel position (x, y) has a ray (inside the map's outline).
  bool contains(double x, double y) const {
    return in_frame(x, y, frame_.size) && self().inside(frame_.plane_x(x), frame_.plane_y(y));
  }

  // True only if every position in [x0, x1] x [y0, y1] has a ray: maps with a convex outline
  // (Derived::kConvexOutline) decide by the four corners; others always say false.
  bool covers(double x0, double y0, double x1, double y1) const {
    if constexpr (!Derived::kConvexOutline) return false;
    return contains(x0, y0) && contains(x1, y0) && contains(x0, y1) && contains(x1, y1);
  }
  Size size() const { return frame_.size; }
  double center_density() const { return frame_.density(); }
  // aspect=keep (MapFrame::keep_square).
  Derived& keep_square() {
    frame_.keep_square();
    return static_cast<Derived&>(*this);
  }
  // The box [-half, half] across, square pixels, centred on the plane's origin.
  Derived& spanned(double half) {
    const double h =
        half * static_cast<double>(frame_.size.height) / static_cast<double>(frame_.size.width);
    frame_.xmin = -half, frame_.xmax = half, frame_.ymin = -h, frame_.ymax = h;
    return static_cast<Derived&>(*this);
  }
  // The part r of the frame as a frame of its own.
  Derived windowed(const PixelRect& r) const {
    Derived q = self();
    q.frame_ = {r.size(), frame_.plane_x(static_cast<double>(r.x0)),
                frame_.plane_x(static_cast<double>(r.x1)),
                frame_.plane_y(static_cast<double>(r.y1)),
                frame_.plane_y(static_cast<double>(r.y0))};
    return q;
  }
  // The same box on a frame of `size`: positions scale with the frame.
  Derived resized(Size size) const {
    Derived q = self();
    q.frame_.size = size;
    return q;
  }
  const MapFrame& frame() const { return frame_; }
  double lon0() const { return lon0_; }

 protected:
  explicit MapProjection(double lon0, MapFrame frame = {}) : lon0_(lon0), frame_(frame) {}
  double lon0_;
  MapFrame frame_;

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

}  // namespace panoproj
