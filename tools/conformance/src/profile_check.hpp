// Expectations for profile telegrams (spec 3.5, D3) derived from a sector table and an angle
// step, and the check that turns them into a byte pattern: fields nobody can predict
// (PROFILECOUNT, time stamps, distances, echoes) become holes, everything else is asserted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/profile.hpp"
#include "session.hpp"

namespace ldoem::conformance {

struct ExpectedSector {
  std::uint16_t sector = 0;
  bool measuring = false;
  std::uint16_t step_ticks = 0;
  std::uint16_t start_dir_ticks = 0;  // a = previous stop + step (spec 3.5 point geometry)
  std::uint16_t end_dir_ticks = 0;    // b = this sector's stop
  std::size_t points = 0;             // (b - a) / step + 1; 0 for a non-measuring sector (D3)
};

// One block per initialised sector in sector-number order, up to the first function 0
// (spec 3.6: it terminates the table). Sector 0 starts one step after the last initialised stop.
std::vector<ExpectedSector> expected_sectors(const std::vector<protocol::SetFunction>& table, std::uint16_t step_ticks);

struct ProfileExpectation {
  std::uint16_t format = protocol::kFormatRange;
  std::optional<std::uint16_t> profile_sent;  // D3: counts from 1 after each GET_PROFILE
  std::vector<ExpectedSector> sectors;
  protocol::SensorMode sensor = protocol::SensorMode::measure;  // S1 rejects anything but MEASURE/OK
};

// Decodes `received` and compares it with the expectation (all asserted fields for the
// emulator; code, format echo and the SENSTAT status byte for a device). Returns the decoded
// profile for further checks.
protocol::Profile check_profile(Session& session, std::string_view what, const ProfileExpectation& expected,
                                ByteView received);

// The baseline (D4) sector table as SET_FUNCTION requests.
std::vector<protocol::SetFunction> baseline_sector_table();

}  // namespace ldoem::conformance
