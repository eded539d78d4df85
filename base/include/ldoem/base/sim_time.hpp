// Time as every pure state machine in ldoem sees it: a duration since an arbitrary epoch,
// passed in by the caller and never read from a clock (D7).
#pragma once

#include <chrono>

namespace ldoem::base {

using SimTime = std::chrono::nanoseconds;

}  // namespace ldoem::base
