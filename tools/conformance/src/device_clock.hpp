// The device's own promise about time, judged from the profiles alone (spec 3.5, D3, D10): one
// revolution every 1/f s of device time, visible in TSTART/TEND and in PROFILECOUNT, whatever
// the host's load. No wall clock is read here, so these checks hold on a starved machine and
// fail only on a device whose clock or counters slip.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/profile.hpp"

namespace ldoem::conformance {

// What one step from a profile to the next in the same stream showed.
struct RevolutionStep {
  std::uint16_t counted = 0;  // PROFILECOUNT advance (mod 65536); > 1 = skipped revolutions
  std::optional<std::uint16_t> t_start_delta_ms;  // first measuring sector's TSTART advance
};

// `previous` then `current` of one stream at `speed_hz`: PROFILESENT advances by exactly one,
// PROFILECOUNT by at least one, and TSTART by PROFILECOUNT's advance times 1000/f ms within
// the clock's 1 ms resolution (two truncated millisecond values differ by less than 1 ms from
// the exact difference). Fields the format leaves out are not judged. An error names the fields.
// `link_lost`: how many broken telegrams the host's transport dropped that no earlier gap used
// up: that many profiles the device sent may be missing, so PROFILESENT may advance by up to
// 1 + link_lost (the clock still has to match PROFILECOUNT exactly).
base::Expected<RevolutionStep, std::string> check_revolution_step(const protocol::Profile& previous,
                                                                   const protocol::Profile& current,
                                                                   std::uint16_t speed_hz, std::uint64_t link_lost = 0);

// Within one profile: every measuring sector is measured within one revolution
// (TEND - TSTART <= 1000/f ms + 1 ms of resolution).
std::optional<std::string> check_within_revolution(const protocol::Profile& profile, std::uint16_t speed_hz);

// Follows one stream after another as the profiles arrive: a GET_PROFILE (start_stream) or a
// change of format starts a new stream whose first profile is compared with nothing.
class DeviceClockCheck {
 public:
  void start_stream() {
    previous_.reset();
    judging_ = true;
  }
  // Profiles that still arrive from a stream already judged (after a failed case, while the
  // baseline's DO_RESET ends it) are not judged again, until the next start_stream.
  void stop_judging() {
    previous_.reset();
    judging_ = false;
  }
  // The head speed the next profiles are measured at (SET_CONFIG global, TRANS_ROTATE f).
  void set_speed_hz(std::uint16_t speed_hz) { speed_hz_ = speed_hz; }
  std::uint16_t speed_hz() const { return speed_hz_; }
  // The verdict on `profile` after the ones before it; a failure names the profiles.
  // `link_lost` as for check_revolution_step.
  std::optional<std::string> next(const protocol::Profile& profile, std::uint64_t link_lost = 0);
  // PROFILESENT's advance at the last step judged (0 for the first profile of a stream).
  std::uint16_t last_sent_step() const { return last_sent_step_; }
  // Revolutions the stream skipped so far (PROFILECOUNT advances beyond one), for reports.
  std::uint64_t skipped_revolutions() const { return skipped_; }

 private:
  std::optional<protocol::Profile> previous_;
  std::uint16_t speed_hz_ = 10;  // D4
  std::uint64_t skipped_ = 0;
  bool judging_ = true;
  std::uint16_t last_sent_step_ = 0;
};

}  // namespace ldoem::conformance
