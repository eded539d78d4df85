#include "ldoem/driver/lifecycle.hpp"

#include <cassert>

namespace ldoem::driver {

LifecycleAction plan_transition(LifecycleState current, LifecycleState target) {
  using S = LifecycleState;
  using A = LifecycleAction;
  if (current == target) {
    return A::none;
  }
  switch (current) {
    case S::unconfigured:
      switch (target) {
        case S::connected: return A::connect;
        case S::closed: return A::close;
        case S::active: return A::refuse;  // connect first: a stream needs a device that answered
        case S::unconfigured: return A::none;
      }
      break;
    case S::connected:
      switch (target) {
        case S::active: return A::start_stream;
        case S::closed: return A::close;
        case S::unconfigured: return A::refuse;  // a handle never forgets it talked; close instead
        case S::connected: return A::none;
      }
      break;
    case S::active:
      switch (target) {
        case S::connected: return A::stop_stream;
        case S::closed: return A::stop_stream_then_close;
        case S::unconfigured: return A::refuse;
        case S::active: return A::none;
      }
      break;
    case S::closed:
      return A::refuse;  // final
  }
  assert(false && "unreachable lifecycle state");
  return A::refuse;
}

std::string_view describe(LifecycleState state) {
  switch (state) {
    case LifecycleState::unconfigured: return "unconfigured";
    case LifecycleState::connected: return "connected";
    case LifecycleState::active: return "active";
    case LifecycleState::closed: return "closed";
  }
  return "unknown";
}

}  // namespace ldoem::driver
