#pragma once
// What differs between the viewers (jobs/tiles/tiles.hpp): level sizes, paths, the config and
// index.html. Internal to the tiles job.
#include <string>
#include <vector>

#include "io/atomic_output.hpp"
#include "jobs/tiles/tiles.hpp"

namespace panoproj {

// Face letters in face order (f r b l u d) and each face's view: yaw, pitch in degrees.
inline constexpr char kFaceLetters[6] = {'f', 'r', 'b', 'l', 'u', 'd'};
inline constexpr double kFaceAngles[6][2] = {{0, 0},   {90, 0}, {180, 0},
                                             {-90, 0}, {0, 90}, {0, -90}};

// The levels for a source of `density` pixels per radian at its centre (checks the job's values).
TilePyramid make_pyramid(const TileSettings& job, double density);

// The viewer's range over a partial panorama: yaw [yaw0, yaw1] (degrees, may pass 180 at the
// back; absent: all round) and pitch [pitch0, pitch1].
struct ViewRange {
  bool full_yaw = true;
  double yaw0 = -180, yaw1 = 180, pitch0 = -90, pitch1 = 90;
  bool partial() const { return !full_yaw || pitch0 > -90 || pitch1 < 90; }
};

// The files besides the tiles.
std::vector<TextFile> viewer_files(const TileSettings& job, const TilePyramid& pyramid,
                                   const ViewRange& range);

// The preview image's path (Marzipano: the faces stacked in order kPreviewOrder) or the
// fallback faces' (Pannellum: one file per face).
inline constexpr char kMarzipanoPreviewOrder[7] = "bdflru";
std::string preview_path(const TilePyramid& pyramid, int face);

}  // namespace panoproj
