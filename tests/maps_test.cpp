// Exported maps: cv::remap given panoproj's maps (OpenCV convention) reproduces panoproj's
// bilinear output within 1 LSB on a smooth image, away from seams, poles and face edges (which
// cv::remap cannot wrap); a 0.5 px slip of the convention fails the same comparison.
#include "panoproj/maps.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "panoproj/convert.hpp"
#include "panoproj/rotation.hpp"
#include "test_support.hpp"

namespace panoproj {
namespace {

struct Compared {
  double worst = 0;
  int64_t pixels = 0;
};

// cv::remap(maps shifted by `slip`) vs panoproj bilinear, over pixels whose bilinear taps lie
// inside the source (one face for cubes).
Compared compare(const char* src_spec, Size ss, const char* dst_spec, Size ds, double yaw,
                 double pitch, float slip) {
  const Projection sp = make_projection(parse_spec(src_spec), ss);
  const Projection dp = make_projection(parse_spec(dst_spec), ds);
  const Eigen::Matrix3d r = rotation_from_ypr(yaw, pitch, 0);
  const Image src = test::render(sp, test::band_limited_scene(0.03, ss.width), PixelType::U8);
  const Image ours = test::fast_remap(src, sp, dp, r, Interp::Bilinear, Engine::Simd, 0);
  const Image map = build_map(sp, dp, r, MapConvention::OpenCV, 0);
  cv::Mat mx(static_cast<int>(ds.height), static_cast<int>(ds.width), CV_32FC1);
  cv::Mat my(mx.size(), CV_32FC1);
  for (int y = 0; y < mx.rows; ++y)
    for (int x = 0; x < mx.cols; ++x) {
      const float* m = reinterpret_cast<const float*>(map.pixel(x, y));
      mx.at<float>(y, x) = m[0] + slip;
      my.at<float>(y, x) = m[1] + slip;
    }
  const cv::Mat in(static_cast<int>(ss.height), static_cast<int>(ss.width), CV_8UC3,
                   const_cast<unsigned char*>(src.data()), src.row_bytes());
  cv::Mat out;
  cv::remap(in, out, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  const auto* cube = std::get_if<Cubemap>(&sp);
  Compared c;
  for (int y = 0; y < mx.rows; ++y)
    for (int x = 0; x < mx.cols; ++x) {
      const float* m = reinterpret_cast<const float*>(map.pixel(x, y));
      if (m[0] < 0) continue;  // no source
      // Taps at floor(m) and floor(m) + 1 (OpenCV convention) must be inside, one face.
      const double lo_x = std::floor(m[0]), lo_y = std::floor(m[1]);
      double x0 = 0, y0 = 0, x1 = static_cast<double>(ss.width), y1 = static_cast<double>(ss.height);
      if (cube) {
        const int f = cube->face_at(m[0] + 0.5, m[1] + 0.5);
        x0 = static_cast<double>(cube->face_origin(f)[0]), y0 = static_cast<double>(cube->face_origin(f)[1]);
        x1 = x0 + static_cast<double>(cube->face_size()), y1 = y0 + static_cast<double>(cube->face_size());
      }
      if (lo_x - 1 < x0 || lo_y - 1 < y0 || lo_x + 2 >= x1 || lo_y + 2 >= y1) continue;
      ++c.pixels;
      for (int ch = 0; ch < 3; ++ch)
        c.worst = std::max(c.worst, std::fabs(double(out.at<cv::Vec3b>(y, x)[ch]) - double(ours.pixel(x, y)[ch])));
    }
  return c;
}

TEST(Maps, CvRemapReproducesPanoprojBilinear) {
  struct C {
    const char* src;
    Size ss;
    const char* dst;
    Size ds;
    double yaw, pitch;
  };
  for (const C& c : {C{"equirect", {1024, 512}, "cubemap", {6 * 256, 256}, 0, 0},
                     C{"equirect", {1024, 512}, "fisheye:fov=180", {512, 512}, 30, 20},
                     C{"cubemap", {6 * 256, 256}, "equirect", {1024, 512}, 0, 0},
                     C{"equirect", {1024, 512}, "pinhole:hfov=90", {640, 480}, 100, -10}}) {
    const Compared ok = compare(c.src, c.ss, c.dst, c.ds, c.yaw, c.pitch, 0.0f);
    std::printf("[maps] %s -> %s: cv::remap vs panoproj bilinear, max %.0f LSB over %lld pixels\n",
                c.src, c.dst, ok.worst, static_cast<long long>(ok.pixels));
    EXPECT_LE(ok.worst, 1.0) << c.src << " -> " << c.dst;
    EXPECT_GT(ok.pixels, c.ds.width * c.ds.height / 2);
    // Half a pixel off (forgetting the convention) is caught.
    EXPECT_GT(compare(c.src, c.ss, c.dst, c.ds, c.yaw, c.pitch, 0.5f).worst, 3.0) << c.src << " -> " << c.dst;
  }
}

TEST(Maps, PanoprojConventionMarksMissingSourcesWithNaN) {
  const Projection sp = make_projection(parse_spec("pinhole:hfov=60"), {100, 80});
  const Projection dp = make_projection(parse_spec("equirect"), {360, 180});
  const Image cv_map = build_map(sp, dp, Eigen::Matrix3d::Identity(), MapConvention::OpenCV, 0);
  const Image pp_map = build_map(sp, dp, Eigen::Matrix3d::Identity(), MapConvention::Panoproj, 0);
  const float* centre_cv = reinterpret_cast<const float*>(cv_map.pixel(180, 90));
  const float* centre_pp = reinterpret_cast<const float*>(pp_map.pixel(180, 90));
  EXPECT_NEAR(centre_pp[0] - centre_cv[0], 0.5f, 1e-5f);
  EXPECT_TRUE(std::isnan(reinterpret_cast<const float*>(pp_map.pixel(0, 0))[0]));
  EXPECT_EQ(reinterpret_cast<const float*>(cv_map.pixel(0, 0))[0], -1.0f);
}

}  // namespace
}  // namespace panoproj
