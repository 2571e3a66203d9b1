#pragma once
// The closed set of projections (projections/list.hpp), their factory and the row forms the
// pipeline uses. Dispatch (std::visit) happens once per row, so inner loops see one concrete type.
#include <cstdint>
#include <variant>

#include "panoproj/spec.hpp"

namespace panoproj {

namespace detail {
template <class Void, class... Types>
struct VariantOf {  // std::variant<Types...> of the list "void, Types..." the macro below makes
  using type = std::variant<Types...>;
};
}  // namespace detail
// Its index is the spec's Kind.
#define PANOPROJ_TYPE_(Type) , Type
using Projection = detail::VariantOf<void PANOPROJ_PROJECTIONS(PANOPROJ_TYPE_)>::type;
#undef PANOPROJ_TYPE_

// Validates the spec against the image size; throws panoproj::Error.
Projection make_projection(const ProjectionSpec& spec, Size size);

// The size at which the projection's centre has `density` pixels per radian (square pixels),
// used when no output size is given. Throws if it would exceed kMaxDefaultPixels.
Size default_size(const ProjectionSpec& spec, double density);
inline constexpr int64_t kMaxDefaultPixels = int64_t{1} << 29;  // 537 Mpx

inline Size size_of(const Projection& p) {
  return std::visit([](const auto& q) { return q.size(); }, p);
}
inline double center_density(const Projection& p) {
  return std::visit([](const auto& q) { return q.center_density(); }, p);
}
inline bool to_ray(const Projection& p, double x, double y, Ray& d) {
  return std::visit([&](const auto& q) { return q.to_ray(x, y, d); }, p);
}
inline bool contains(const Projection& p, double x, double y) {
  return std::visit([&](const auto& q) { return q.contains(x, y); }, p);
}
inline bool to_pixel(const Projection& p, const Ray& d, double& x, double& y) {
  return std::visit([&](const auto& q) { return q.to_pixel(d, x, y); }, p);
}

// The source position of target pixel position (px, py): dst's ray there, turned by rotation,
// seen by src; false where either has none (the exact per-point map).
inline bool source_pixel(const Projection& src, const Projection& dst, const Eigen::Matrix3d& rotation, double px,
                         double py, double& sx, double& sy) {
  Ray d;
  return to_ray(dst, px, py, d) && to_pixel(src, rotation * d, sx, sy);
}

// Rays through the pixel centres (x0 + i + centre, y), i < n; ok[i] = 0 where there is none.
void to_ray_row(const Projection& p, double y, int64_t x0, int64_t n, Ray* rays, uint8_t* ok,
                double centre = 0.5);

// Where the samples of a plane sit in its frame, in pixels from the pixel centres: sample (i, j)
// of the target at (i + 0.5 + target_x, j + 0.5 + target_y), and a source position p read at
// p - source (a chroma plane's siting: video/ChromaSiting). Zero for images.
struct Siting {
  double source_x = 0, source_y = 0, target_x = 0, target_y = 0;
  bool any() const { return source_x != 0 || source_y != 0 || target_x != 0 || target_y != 0; }
  // The same on the target at n times its size (its sub-pixels).
  Siting on_sub_target(int n) const { return {source_x, source_y, target_x * n, target_y * n}; }
};
// Whether the projection shows the whole sphere (cubemap, full equirect, the world maps): a
// conversion to it reaches (nearly) every pixel of any source.
bool shows_whole_sphere(const Projection& p);
// The same projection on a frame of `size` showing the same field: pixel positions scale by
// size / size_of(p) per axis (mip levels, supersampled targets). A cubemap's size must hold
// whole faces in its layout. Throws panoproj::Error otherwise.
Projection rescaled(const Projection& p, Size size);
// The part r of p's frame as a frame of its own: pixel (i, j) of it is p's pixel (r.x0 + i,
// r.y0 + j), the same rays (to rounding). For the forms has_window says; else InternalError.
bool has_window(const Projection& p);
Projection windowed(const Projection& p, const PixelRect& r);
// Pixels of rays[i] where ok[i] (in/out: cleared where the ray has no pixel).
void to_pixel_row(const Projection& p, const Ray* rays, int64_t n, double* xs, double* ys,
                  uint8_t* ok);

}  // namespace panoproj
