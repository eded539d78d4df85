// Steps several case groups share: clock checks with a tolerance from --time-scale, profile
// streams on the baseline configuration, silence checks counted in revolutions.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "ldoem/protocol/messages.hpp"
#include "profile_check.hpp"
#include "session.hpp"

namespace ldoem::conformance {

// The reply WORD at payload offset 2 is a clock value that was `nominal_ms` at `loaded_at`
// (wall time just before the request that set it). Real time: it may have advanced by up to
// the simulated time elapsed since then, rounded up, plus 1 ms of clock resolution.
// Virtual time: it must equal nominal_ms. The rest of the reply must match `reply` exactly.
void check_clock_reply(Session& session, std::string_view what, const Bytes& reply, const Arrival& received,
                       Clock::time_point loaded_at);

// Baseline expectation (D4 table, 4 ticks) for a profile of `format` with PROFILESENT `sent`.
ProfileExpectation baseline_profile(std::uint16_t format, std::uint16_t sent);

// One revolution at `speed_hz`, in wall time, but never below 20 ms (scheduling slack).
std::chrono::milliseconds revolutions_wall(const Session& session, double revolutions, std::uint16_t speed_hz);

// GET_PROFILE(count, format) from MEASURE, first profile waited for up to the reply timeout.
Arrival start_profiles(Session& session, std::uint16_t count, std::uint16_t format);

// CANCEL_PROFILE and its reply (status MEASURE), skipping profiles sent before it.
void cancel_profiles(Session& session);

// The clock word of a GET_SYNC_CLOCK-style reply.
std::uint16_t clock_word(ByteView reply);

}  // namespace ldoem::conformance
