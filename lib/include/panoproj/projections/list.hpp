#pragma once
// The closed list of projection types, in catalogue order: one include and one X(Type) line each.
// Kind (spec.hpp), the Projection variant (projection.hpp) and the table of projection modules
// (lib/src/projections/module.hpp: catalogue entries, validation, construction, default size,
// rescaling, one file per type) are generated from it.
#include "panoproj/projections/aitoff.hpp"
#include "panoproj/projections/bonne.hpp"
#include "panoproj/projections/calibrated_lens.hpp"
#include "panoproj/projections/cubemap.hpp"
#include "panoproj/projections/cylindrical.hpp"
#include "panoproj/projections/cylindrical_map.hpp"
#include "panoproj/projections/dual_fisheye.hpp"
#include "panoproj/projections/equirect.hpp"
#include "panoproj/projections/fisheye.hpp"
#include "panoproj/projections/gopro_max.hpp"
#include "panoproj/projections/hammer.hpp"
#include "panoproj/projections/mollweide.hpp"
#include "panoproj/projections/panini.hpp"
#include "panoproj/projections/panotools.hpp"
#include "panoproj/projections/pinhole.hpp"
#include "panoproj/projections/transverse_mercator.hpp"

#define PANOPROJ_PROJECTIONS(X) \
  X(Pinhole)                    \
  X(Fisheye)                    \
  X(DualFisheye)                \
  X(CalibratedLens)             \
  X(PanoTools)                  \
  X(Equirect)                   \
  X(Cylindrical)                \
  X(Cubemap)                    \
  X(GoProMax)                   \
  X(Panini)                     \
  X(Aitoff)                     \
  X(Hammer)                     \
  X(Bonne)                      \
  X(Mollweide)                  \
  X(CylindricalMap)             \
  X(TransverseMercator)
