#pragma once
// A video's spherical metadata (Spherical Video V2 as FFmpeg's libraries carry it) as the convert
// job reads and writes it:
//   - read: an equirect (full, or cropped by its bounds: the frame is that part of the whole
//     panorama) or a cube in layout 0 (3x2, right left up / down front back, upright: FFmpeg's
//     c3x2 default order rludfb; its padding as pad_px) gives the source spec, with the stereo
//     layout (top-bottom, left-right: left eye first); the pose levels it. Other projections
//     and stereo layouts are refused in one line asking for --from.
//   - pose: FFmpeg's R = r_y(yaw) r_x(pitch) r_z(roll) (libavutil/spherical.h: positive yaw turns
//     the sphere in front of the viewer to the right, pitch up, roll to the right), a frame ray
//     to a level one: rotation_from_ypr(yaw, pitch, roll) in panoproj's convention.
//   - written: an equirect target (its bounds; a crop across the back seam has none) and a 3x2
//     cube in layout 0's order, unturned and unpadded, with the stereo layout; the pose is level
//     (the output is the view asked for). Others get none, with the reason.
#include <optional>
#include <string>

#include "io/video_plugin.hpp"
#include "panoproj/convert.hpp"
#include "panoproj/spec.hpp"

namespace panoproj {

// The source spec the metadata describes for frames of `size`; throws Error naming `input`.
std::string spherical_source_spec(const SphericalVideo& v, Size size, const std::string& input);

// Whether two specs say the same projection (numbers within 1e-6).
bool same_spec(const ProjectionSpec& a, const ProjectionSpec& b);

// The frame -> level rotation of the metadata's pose.
Eigen::Matrix3d spherical_pose(const SphericalVideo& v);

// The metadata of a target; none with `why` set where the target has none.
SphericalVideo spherical_of_target(const ConversionGeometry& g, std::string& why);

// A line saying what the metadata holds ("equirect, cropped 0.25 left 0.25 right, stereo
// top-bottom, pose yaw 10 pitch 0 roll 0").
std::string spherical_text(const SphericalVideo& v);

}  // namespace panoproj
