// timing/: spin-up (D7) and profile cadence checked in simulated time, so a daemon running at
// --time-scale X is judged by its own clock (device clock WORDs, TSTART) and, where the wall
// clock is involved, by wall = simulated / X. d10/: no profile after a reply that ends a stream.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "case_steps.hpp"
#include "cases.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;
using std::chrono::milliseconds;

std::string ms_text(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", ms);
  return text;
}

double wall_ms(Clock::duration duration) { return std::chrono::duration<double, std::milli>(duration).count(); }

// D7: 0 to 10 Hz in about 2 s of simulated time; the suite accepts 1.5 .. 2.5 s.
constexpr double kSpinUpMinMs = 1500;
constexpr double kSpinUpMaxMs = 2500;
// Spec 6: S2 allows 10 s for the TRANS_ROTATE reply; the bound for a real device.
constexpr double kDeviceSpinUpMaxMs = 10000;
// Wall-clock slack for a request/reply round trip on a loaded host.
constexpr double kWallLatencyMs = 50;

void spin_up(Session& session) {
  // A head that turned in an earlier case coasts down first (D7 models spin-up; give it 3 s).
  session.sleep_simulated(SimMilliseconds(3000));
  const Arrival clock_before = session.request(encode_request(GetSyncClock{}));
  const Clock::time_point sent_at = Clock::now();
  session.send(encode_request(TransRotate{0}));
  session.send(encode_request(GetStatus{}));
  // GET_STATUS is answered during the spin-up: ROTATE with motor "spin too low" (lead decision).
  auto during = session.receive(Clock::now() + session.options().reply_timeout);
  if (!during) throw CaseFailed("no reply to GET_STATUS sent during the spin-up");
  session.check("GET_STATUS during spin-up",
                session.pattern(reply_bytes(GetStatusReply{status(SensorMode::rotate, MotorMode::spin_too_low), {}})),
                during->payload);
  auto rotated = session.receive(sent_at + session.reply_wait_after(SimMilliseconds(10000)));
  if (!rotated) throw CaseFailed("no TRANS_ROTATE reply within 10 s simulated (spec 6: S2's limit)");
  session.check("TRANS_ROTATE reply", session.pattern(session.reply_vector("TRANS_ROTATE → ROTATE, motor OK")),
                rotated->payload);
  const Arrival clock_after = session.request(encode_request(GetSyncClock{}));

  const double scale = session.options().virtual_time ? 0.0 : session.options().time_scale;
  const double device_ms = static_cast<std::uint16_t>(clock_word(clock_after.payload) - clock_word(clock_before.payload));
  // The device clock also ran while the two GET_SYNC_CLOCK round trips were under way.
  const double overhead_ms = (wall_ms(sent_at - clock_before.at) + wall_ms(clock_after.at - rotated->at)) * scale + 2;
  const double spin_wall_ms = wall_ms(rotated->at - sent_at);
  const double min_ms = session.emulator_target() ? kSpinUpMinMs : 0;
  const double max_ms = session.emulator_target() ? kSpinUpMaxMs : kDeviceSpinUpMaxMs;
  std::ostringstream numbers;
  numbers << "device clock " << device_ms << " ms (minus up to " << overhead_ms << " ms of round trips), wall "
          << spin_wall_ms << " ms at --time-scale " << session.options().time_scale;
  const std::string expected_range = "; expected " + std::to_string(int(min_ms)) + ".." + std::to_string(int(max_ms)) +
                                     " ms simulated";
  // Too fast is the device's fault whatever the load. Too slow can be a starved daemon: its
  // clock runs on while it waits for a CPU and answers late (L-time-1), so the probe judges that,
  // with the slack this window leaves in wall time at this scale.
  if (device_ms + 1 < min_ms) throw CaseFailed("spin-up took " + numbers.str() + expected_range);
  if (device_ms - overhead_ms - 1 > max_ms) {
    const double slack_wall_ms = session.options().virtual_time ? 0 : (max_ms - min_ms) / 2 / session.options().time_scale;
    throw WallClockFailed("spin-up took " + numbers.str() + expected_range, slack_wall_ms);
  }
  if (!session.options().virtual_time) {
    const double scale_now = session.options().time_scale;
    const double wall_min = min_ms / scale_now - 5;
    const double wall_max = max_ms / scale_now + kWallLatencyMs;
    if (spin_wall_ms < wall_min || spin_wall_ms > wall_max) {
      throw WallClockFailed("spin-up took " + numbers.str() + "; expected " + ms_text(wall_min) + ".." +
                                ms_text(wall_max) + " ms wall (simulated / time scale)",
                            kWallLatencyMs);
    }
  }
}

struct Stream {
  std::vector<Profile> profiles;
  std::vector<Clock::time_point> arrivals;
};

Stream collect(Session& session, const ProfileExpectation& base, std::uint16_t speed_hz, int count) {
  Stream stream;
  session.send(encode_request(GetProfile{0, base.format}));
  for (int i = 1; i <= count; ++i) {
    ProfileExpectation expected = base;
    expected.profile_sent = session.emulator_target() ? std::optional<std::uint16_t>(i) : std::nullopt;  // D3
    const std::string what = "profile " + std::to_string(i);
    const auto wait = i == 1 ? session.reply_wait_after(SimMilliseconds(400))
                             : revolutions_wall(session, 3, speed_hz) + session.options().reply_timeout;
    const Arrival arrival = session.await_profile(what, wait);
    stream.profiles.push_back(check_profile(session, what, expected, arrival.payload));
    stream.arrivals.push_back(arrival.at);
  }
  cancel_profiles(session);
  return stream;
}

const SectorBlock& first_measuring(const Profile& profile, const ProfileExpectation& expected) {
  for (std::size_t i = 0; i < expected.sectors.size() && i < profile.sectors.size(); ++i) {
    if (expected.sectors[i].measuring) return profile.sectors[i];
  }
  throw CaseFailed("the profile has no measuring sector");
}

// Spec 3.5 / 6: one profile per revolution, TSTART 1000/f ms apart (16-bit wrap aware), times
// the number of revolutions between the two (D10 lets a slow link skip revolutions; it must
// then show in PROFILECOUNT while PROFILESENT stays consecutive).
void check_cadence(Session& session, const Stream& stream, const ProfileExpectation& expected, std::uint16_t speed_hz) {
  const int period_ms = 1000 / speed_hz;
  std::ostringstream deltas;
  bool bad = false;
  std::uint32_t revolutions = 0;
  for (std::size_t i = 1; i < stream.profiles.size(); ++i) {
    const Profile& previous = stream.profiles[i - 1];
    const Profile& current = stream.profiles[i];
    if (static_cast<std::uint16_t>(current.profile_sent - previous.profile_sent) != 1) {
      throw CaseFailed("PROFILESENT " + std::to_string(previous.profile_sent) + " then " +
                       std::to_string(current.profile_sent) + ": not consecutive (spec 3.5, D10)");
    }
    const auto counted = static_cast<std::uint16_t>(current.profile_count - previous.profile_count);
    if (counted == 0) throw CaseFailed("PROFILECOUNT did not advance between profiles " + std::to_string(i) + " and " +
                                       std::to_string(i + 1));
    revolutions += counted;
    const auto delta = static_cast<std::uint16_t>(first_measuring(current, expected).t_start_ms -
                                                  first_measuring(previous, expected).t_start_ms);
    const int want = counted * period_ms;
    deltas << (i > 1 ? ", " : "") << delta;
    if (counted != 1) deltas << "(x" << counted << ")";
    if (std::abs(int(delta) - want) > 1) bad = true;  // 1 ms clock resolution
  }
  if (bad) {
    throw CaseFailed("TSTART deltas [" + deltas.str() + "] ms; expected " + std::to_string(period_ms) +
                     " ms per revolution at " + std::to_string(speed_hz) + " Hz (+-1 ms)");
  }
  for (std::size_t i = 0; i < stream.profiles.size(); ++i) {
    const SectorBlock& sector = first_measuring(stream.profiles[i], expected);
    const auto span = static_cast<std::uint16_t>(sector.t_end_ms - sector.t_start_ms);
    if (span > period_ms) {
      throw CaseFailed("profile " + std::to_string(i + 1) + ": TEND - TSTART = " + std::to_string(span) +
                       " ms, longer than one revolution (" + std::to_string(period_ms) + " ms)");
    }
  }
  if (session.options().virtual_time) return;
  const double expected_wall = revolutions * double(period_ms) / session.options().time_scale;
  const double measured_wall = wall_ms(stream.arrivals.back() - stream.arrivals.front());
  if (std::abs(measured_wall - expected_wall) > 0.3 * expected_wall + kWallLatencyMs) {
    // How far each arrival fell behind its own TSTART (relative to the first profile): a
    // growing lag means profiles queue up behind the link, which D10 forbids.
    std::ostringstream lags;
    const auto t0 = first_measuring(stream.profiles.front(), expected).t_start_ms;
    for (std::size_t i = 0; i < stream.profiles.size(); ++i) {
      const auto since_ms = static_cast<std::uint16_t>(first_measuring(stream.profiles[i], expected).t_start_ms - t0);
      const double lag = wall_ms(stream.arrivals[i] - stream.arrivals.front()) - since_ms / session.options().time_scale;
      lags << (i > 0 ? ", " : "") << ms_text(lag);
    }
    throw WallClockFailed("profiles arrived over " + ms_text(measured_wall) + " ms wall for " +
                     std::to_string(revolutions) + " revolutions; expected " + ms_text(expected_wall) +
                     " ms (simulated / time scale, +-30 % + 50 ms); arrival lag behind TSTART/X [" + lags.str() +
                     "] ms wall",
                          0.3 * expected_wall + kWallLatencyMs);
  }
}

void cadence(Session& session, std::uint16_t speed_hz, std::uint16_t step_ticks, std::optional<std::uint16_t> clock_ms) {
  session.set_global(1, speed_hz, step_ticks);
  session.enter_rotate();
  if (clock_ms) {
    session.expect("SET_TIME_ABS in ROTATE", encode_request(SetTimeAbs{*clock_ms}),
                   session.pattern(reply_bytes(SetTimeAbsReply{*clock_ms}), {0, 1, 2, 3}));
  }
  session.enter_measure();
  ProfileExpectation expected;
  expected.format = kFormatRange;
  expected.sectors = expected_sectors(baseline_sector_table(), step_ticks);
  const Stream stream = collect(session, expected, speed_hz, 12);
  check_cadence(session, stream, expected, speed_hz);
}

void profile_count_then_stop(Session& session) {
  session.enter_rotate();
  session.enter_measure();
  session.send(encode_request(GetProfile{3, kFormatRange}));
  for (std::uint16_t sent = 1; sent <= 3; ++sent) {
    ProfileExpectation expected = baseline_profile(kFormatRange, sent);
    if (!session.emulator_target()) expected.profile_sent.reset();
    const Arrival arrival = session.await_profile("profile " + std::to_string(sent),
                                                  session.reply_wait_after(SimMilliseconds(400)));
    check_profile(session, "profile " + std::to_string(sent), expected, arrival.payload);
  }
  session.expect_silence("after 3 of GET_PROFILE 3", revolutions_wall(session, 3, 10) + milliseconds(50));
}

// D10: after the reply to a request that ends the stream, not one more profile.
void stream_then(Session& session, std::uint16_t speed_hz, std::string_view what, const Bytes& request,
                 const BytePattern& reply) {
  if (speed_hz != 10) session.set_global(1, speed_hz, 8);
  session.enter_rotate();
  session.enter_measure();
  start_profiles(session, 0, kFormatRange);
  session.await_profile("second profile", revolutions_wall(session, 3, speed_hz) + session.options().reply_timeout);
  session.expect(what, request, reply, session.reply_wait_after(SimMilliseconds(10000)));
  session.expect_silence(std::string("after the ") + std::string(what) + " reply",
                         revolutions_wall(session, 4, speed_hz) + milliseconds(50));
}

}  // namespace

void add_spin_up_cases(std::vector<Case>& cases) {
  cases.push_back(Case{"timing/TRANS_ROTATE_spin_up_0_to_10_Hz", spin_up, false, true, {}});
}

void add_timing_cases(std::vector<Case>& cases) {
  cases.push_back(Case{"timing/profile_cadence_5_Hz", [](Session& s) { cadence(s, 5, 4, std::nullopt); },
                       false, true, {}});
  cases.push_back(Case{"timing/profile_cadence_10_Hz", [](Session& s) { cadence(s, 10, 4, std::nullopt); },
                       false, true, {}});
  // 20 Hz needs step >= 0.5 deg: 720 * 20 = 14400 Hz, the maximum pulse frequency (spec 5).
  cases.push_back(Case{"timing/profile_cadence_20_Hz", [](Session& s) { cadence(s, 20, 8, std::nullopt); },
                       false, true, {}});
  // The clock set 500 ms before its wrap: TSTART deltas must be taken modulo 65536 (spec 2.3).
  cases.push_back(Case{"timing/profile_cadence_10_Hz_across_clock_wrap", [](Session& s) { cadence(s, 10, 4, 65036); },
                       false, true, {}});
  cases.push_back(Case{"timing/GET_PROFILE_3_then_stop", profile_count_then_stop, false, true, {}});
  cases.push_back(Case{"d10/no_profile_after_CANCEL_PROFILE_reply_20_Hz",
                       [](Session& s) {
                         stream_then(s, 20, "CANCEL_PROFILE", encode_request(CancelProfile{}),
                                     s.pattern(s.reply_vector("CANCEL_PROFILE, MEASURE")));
                       },
                       true, true, {}});
  cases.push_back(Case{"d10/no_profile_after_TRANS_ROTATE_reply",
                       [](Session& s) {
                         stream_then(s, 10, "TRANS_ROTATE", encode_request(TransRotate{0}),
                                     s.pattern(s.reply_vector("TRANS_ROTATE → ROTATE, motor OK")));
                       },
                       true, true, {}});
  cases.push_back(Case{"d10/no_profile_after_DO_RESET_2_reply",
                       [](Session& s) {
                         stream_then(s, 10, "DO_RESET 2", encode_request(DoReset{reset_level::kHaltToIdle}),
                                     s.pattern(s.reply_vector("DO_RESET level 2")));
                       },
                       true, true, {}});
}

}  // namespace ldoem::conformance
