// The lifecycle of a device handle (design.md convention 2): every (current, target) pair is
// decided in plan_transition, one switch, tested exhaustively. Moving to the current state
// succeeds (as D2 does for the device's own transitions); Closed refuses everything else.
//
//   Unconfigured  transport open, nothing said yet; no service may be called
//   Connected     GET_STATUS answered: services may be called
//   Active        a GET_PROFILE stream is running: next_profile() yields profiles
//   Closed        transport closed; final
#pragma once

#include <cstdint>
#include <string_view>

namespace ldoem::driver {

enum class LifecycleState : std::uint8_t { unconfigured, connected, active, closed };

// What the Scanner does to go from one state to another.
enum class LifecycleAction : std::uint8_t {
  none,                    // already there
  connect,                 // GET_STATUS; success -> Connected
  start_stream,            // GET_PROFILE with the Scanner's stream options -> Active
  stop_stream,             // CANCEL_PROFILE -> Connected
  close,                   // close the transport -> Closed
  stop_stream_then_close,  // CANCEL_PROFILE (its failure does not keep us open), close
  refuse,                  // not a transition the handle offers: wrong_state
};

LifecycleAction plan_transition(LifecycleState current, LifecycleState target);

std::string_view describe(LifecycleState state);

}  // namespace ldoem::driver
