#pragma once
// Stopping a long job from its caller. A job's calling thread runs the check set for it between
// units of work (the tasks it hands itself, tile bands, views, frames) and once more before its
// output lands; the check throws to stop the job, which then writes nothing (Python's module
// raises KeyboardInterrupt this way on Ctrl-C while the GIL is released; the panoproj command
// stops by its signal handlers instead).
#include <functional>

namespace panoproj {

// The check for jobs run on this thread (none: {}); returns the one it replaces.
std::function<void()> set_interrupt_check(std::function<void()> check);
// Runs this thread's check, if any.
void check_interrupt();

}  // namespace panoproj
