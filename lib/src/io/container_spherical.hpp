#pragma once
// Google's Spherical Video V2 metadata read (and, in MP4, written) by panoproj itself where
// FFmpeg's libraries are not at hand (video through PyAV, which neither gives nor takes it), with
// the meanings libavformat gives it (io/video/backend.cpp): bounds in 0.32 fixed point, angles in
// 16.16.
//   - MP4 (ISO BMFF): sv3d (proj: prhd, equi, cbmp, mshp) and st3d (0 mono, 1 top-bottom,
//     2 left-right) in the video track's sample entry (moov/trak/mdia/minf/stbl/stsd/<entry>),
//     and V1's uuid XML in the trak (read only).
//   - Matroska and WebM (read only): the video track's Projection element (its type, private
//     data: an equi or cbmp box's payload, and pose) and StereoMode.
#include <string>
#include <string_view>

#include "io/video_plugin.hpp"

namespace panoproj {

// The metadata of video track `stream` (the file's stream index: its trak's place among the
// traks), none where it has none. Throws Error naming `what` where a box is malformed (sizes past
// their parent, bounds that cross, as libavformat refuses them).
SphericalVideo spherical_of_moov(std::string_view moov, int stream, const std::string& what);
// The moov box (header included) of the file at `path`, "" where it has none (or it is over
// 256 MB); `last`: whether it ends the file.
std::string read_moov(const std::string& path, bool* last = nullptr);

// The metadata of video track `stream` (its TrackEntry's place among the tracks) of the Matroska
// file at `path` (its Tracks element within the first 16 MB), none where it has none; Error
// naming `what` where the element is malformed or says what libavformat refuses.
SphericalVideo read_matroska_spherical(const std::string& path, int stream,
                                       const std::string& what);
// The same from the file's first bytes.
SphericalVideo spherical_of_matroska(std::string_view head, int stream, const std::string& what);

// `moov` with `v`'s sv3d and st3d boxes at the end of its first video track's sample entry
// (the parents' sizes grown); Error where it has no video track, already has either box, or a
// parent box of 64-bit size.
std::string moov_with_spherical(std::string_view moov, const SphericalVideo& v);
// Writes `v` into the finished MP4 at `fd` whose moov ends it (rewritten in place, longer);
// Error naming `path` where the file is not laid out so.
void write_mp4_spherical(int fd, const std::string& path, const SphericalVideo& v);

}  // namespace panoproj
