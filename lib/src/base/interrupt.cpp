#include "panoproj/interrupt.hpp"

#include <utility>

namespace panoproj {
namespace {
thread_local std::function<void()> tls_check;
}  // namespace

std::function<void()> set_interrupt_check(std::function<void()> check) { return std::exchange(tls_check, std::move(check)); }

void check_interrupt() {
  if (tls_check) tls_check();
}

}  // namespace panoproj
