#include "case_steps.hpp"

#include <algorithm>
#include <cmath>

namespace ldoem::conformance {

using namespace protocol;

std::uint16_t clock_word(ByteView reply) { return reply.size() >= 4 ? read_word_be(reply, 2) : 0; }

void check_clock_reply(Session& session, std::string_view what, const Bytes& reply, const Arrival& received,
                       Clock::time_point loaded_at) {
  BytePattern pattern = BytePattern::exactly(reply);
  session.check(what, pattern.with_hole(2, 2), received.payload);
  const std::uint16_t nominal = clock_word(reply);
  const std::uint16_t value = clock_word(received.payload);
  const auto advance_ms = static_cast<std::uint16_t>(value - nominal);  // 16-bit wrap (spec 2.3)
  std::int64_t allowed_ms = 0;
  if (!session.options().virtual_time) {
    const double elapsed_ms = std::chrono::duration<double, std::milli>(received.at - loaded_at).count();
    allowed_ms = static_cast<std::int64_t>(std::ceil(elapsed_ms * session.options().time_scale)) + 1;
  }
  if (advance_ms > allowed_ms) {
    auto mismatch = compare(pattern, received.payload);
    throw CaseFailed(std::string(what) + ": clock " + std::to_string(value) + " ms is " +
                         std::to_string(static_cast<std::int16_t>(advance_ms)) + " ms from the expected " +
                         std::to_string(nominal) + " ms (allowed advance 0.." + std::to_string(allowed_ms) + " ms)",
                     mismatch ? render_diff(pattern, received.payload, *mismatch) : std::string{});
  }
}

ProfileExpectation baseline_profile(std::uint16_t format, std::uint16_t sent) {
  ProfileExpectation expected;
  expected.format = format;
  expected.profile_sent = sent;
  expected.sectors = expected_sectors(baseline_sector_table(), 4);
  return expected;
}

std::chrono::milliseconds revolutions_wall(const Session& session, double revolutions, std::uint16_t speed_hz) {
  const auto simulated = SimMilliseconds(static_cast<std::int64_t>(std::ceil(revolutions * 1000.0 / speed_hz)));
  return std::max(session.wall_for(simulated), std::chrono::milliseconds(20));
}

Arrival start_profiles(Session& session, std::uint16_t count, std::uint16_t format) {
  session.send(encode_request(GetProfile{count, format}));
  // Spec 6: S1 notes the first profile may take a few seconds; it still waits 5 s.
  return session.await_profile("first profile after GET_PROFILE", session.reply_wait_after(SimMilliseconds(400)));
}

void cancel_profiles(Session& session) {
  session.expect("CANCEL_PROFILE", encode_request(CancelProfile{}),
                 session.pattern(session.reply_vector("CANCEL_PROFILE, MEASURE")));
}

}  // namespace ldoem::conformance
