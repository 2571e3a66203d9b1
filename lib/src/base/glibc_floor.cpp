// Portable builds only (PANOPROJ_PORTABLE: the wheel, manylinux_2_34, glibc 2.34 and up). The link
// wraps two functions newer glibc versions gave us (-Wl,--wrap=...):
// - hypot: glibc 2.35 gave it a new symbol version (hypot@GLIBC_2.35, without the old SVID error
//   wrapper); calls land on the version every glibc has, which computes the same value.
// - arc4random (glibc 2.36): libstdc++.a's std::random_device refers to it, and libstdc++ is
//   linked statically; panoproj never draws from it, and the wrapper reads getrandom (2.25).
#include <sys/random.h>

#include <cstdint>
#include <cstdlib>

extern "C" double panoproj_hypot_2_2_5(double, double);
__asm__(".symver panoproj_hypot_2_2_5, hypot@GLIBC_2.2.5");
extern "C" double __wrap_hypot(double x, double y) { return panoproj_hypot_2_2_5(x, y); }

extern "C" uint32_t __wrap_arc4random() {
  uint32_t r = 0;
  if (getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) std::abort();  // as arc4random: never fails
  return r;
}
