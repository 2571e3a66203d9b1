#pragma once
// Cartographic plane <-> pixels: the map's bounding box [xmin, xmax] x [ymin, ymax] fills the
// frame, north (+Y) up. Longitudes are taken relative to the central meridian lon0.
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
};

}  // namespace panoproj
