// Windows (projection.hpp: windowed): the part of a frame as a frame of its own has the rays of
// that part, for every case-table row whose form has windows, at its corners and inside.
#include <gtest/gtest.h>

#include "panoproj/error.hpp"
#include "panoproj/projection.hpp"
#include "projections/module.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

TEST(Window, EveryCaseRowsWindowHasThatPartsRaysAndPixels) {
  int checked = 0;
  for (const ProjectionCase& row : projection_cases())
    for (const Size size : row.sizes) {
      if (size.width < 8 || size.height < 8 || size.width * size.height > 40000000) continue;
      const Projection p = make_projection(parse_spec(row.spec), size);
      if (!has_window(p)) continue;
      const PixelRect r{size.width / 5, size.height / 3, size.width / 5 + size.width / 2,
                        size.height / 3 + size.height / 2};
      const Projection w = windowed(p, r);
      ASSERT_EQ(size_of(w), r.size());
      for (const double fx : {0.0, 0.25, 0.5, 0.999, 1.0})
        for (const double fy : {0.0, 0.4, 0.999, 1.0}) {
          const double x = fx * static_cast<double>(r.width()),
                       y = fy * static_cast<double>(r.height());
          Ray a, b;
          const bool ha =
              to_ray(p, x + static_cast<double>(r.x0), y + static_cast<double>(r.y0), a);
          ASSERT_EQ(ha, to_ray(w, x, y, b))
              << row.spec << " " << size.width << " at " << x << "," << y;
          if (!ha) continue;
          EXPECT_LT((a - b).norm(), 1e-12 * (1 + static_cast<double>(size.width))) << row.spec;
          double px, py;
          if (to_pixel(w, a, px, py)) {
            EXPECT_NEAR(px, x, 1e-6) << row.spec;
            EXPECT_NEAR(py, y, 1e-6) << row.spec;
          }
          ++checked;
        }
    }
  EXPECT_GT(checked, 500);
}

TEST(Window, FormsWithoutOneSayNoAndRefuse) {
  const Projection cube = make_projection(parse_spec("cubemap"), {600, 100});
  EXPECT_FALSE(has_window(cube));
  EXPECT_THROW(windowed(cube, {0, 0, 10, 10}), InternalError);
}

}  // namespace
}  // namespace panoproj
