// The photometric keys (photometric_keys.hpp).
#include "spec/photometric_keys.hpp"

#include <cmath>
#include <cstdlib>

#include "panoproj/error.hpp"

namespace panoproj {
namespace {

constexpr const char* kKeys[] = {"response", "ev", "wb", "vignetting", "vignetting_centre"};

ParamDef text(const char* key, const char* help) {
  return {key, ParamType::Text, "", 0, 0, false, false, "", help};
}

}  // namespace

std::vector<ParamDef> photometric_key_defs(bool two_lenses) {
  std::vector<ParamDef> d{
      text("response",
           "the camera response: emor (EMoR's mean curve, Hugin's default), linear, or the EMoR "
           "coefficients Ra/Rb/Rc/Rd/Re; default emor for integer images, linear for float ones"),
      {"ev", ParamType::Number, "0", -100, 100, false, false, "",
       "the image's exposure value (Hugin's Eev); on a target, the output's (default: the mean "
       "of the source's lenses)"},
      text("wb", "white balance R/B: red divided by R, blue by B (Hugin's Er/Eb)"),
      text("vignetting",
           "a/b/c/d: the vignetting a + b r^2 + c r^4 + d r^6 divided out (Hugin's Va..Vd), r "
           "from the image's centre over its half diagonal"),
      text("vignetting_centre", "X/Y: the vignetting centre's shift from the image's (pixels)")};
  if (two_lenses) {
    d.push_back({"ev2", ParamType::Number, "", -100, 100, false, false, "",
                 "lens 1's exposure value; default: ev"});
    d.push_back(text("wb2", "lens 1's white balance R/B; default: wb"));
    d.push_back(text("vignetting2", "lens 1's vignetting a/b/c/d; default: vignetting"));
    d.push_back(text("vignetting_centre2",
                     "lens 1's vignetting centre shift X/Y; default: "
                     "vignetting_centre"));
  }
  return d;
}

bool gives_photometry(const ProjectionSpec& s) {
  for (const char* k : kKeys)
    if (s.given(k) || s.given(std::string(k) + "2")) return true;
  return false;
}

PhotometricKeys photometric_keys(const ProjectionSpec& s, int lens) {
  // Lens 1's key where given, else lens 0's.
  const auto key = [&](const std::string& k) {
    return lens == 1 && s.given(k + "2") ? k + "2" : k;
  };
  PhotometricKeys p;
  if (s.given("response")) {
    const std::string r = s.choice("response");
    p.linear = r == "linear";
    if (r != "linear" && r != "emor") {
      const auto c =
          s.numbers("response", 5, 5, "emor, linear or five EMoR coefficients Ra/Rb/Rc/Rd/Re");
      p.emor = std::array<double, 5>{c[0], c[1], c[2], c[3], c[4]};
    }
  }
  if (const std::string k = key("ev"); s.given(k)) p.ev = *s.number(k);
  if (const std::string k = key("wb"); s.given(k)) {
    const auto c = s.numbers(k, 2, 2, "two multipliers R/B");
    p.red = c[0], p.blue = c[1];
  }
  if (const std::string k = key("vignetting"); s.given(k)) {
    const auto c = s.numbers(k, 1, 4, "1 to 4 coefficients a/b/c/d");
    for (size_t i = 0; i < 4; ++i) p.vignetting[i] = i < c.size() ? c[i] : 0.0;
  }
  if (const std::string k = key("vignetting_centre"); s.given(k)) {
    const auto c = s.numbers(k, 2, 2, "a shift X/Y in pixels");
    p.shift_x = c[0], p.shift_y = c[1];
  }
  return p;
}

}  // namespace panoproj
