#include "device_clock.hpp"

#include <cmath>
#include <cstdio>

namespace ldoem::conformance {
namespace {

using namespace protocol;

bool has_field(const Profile& profile, std::uint16_t bit) { return (profile.format & bit) != 0; }

// The first sector with points: the one whose TSTART marks a measured sweep (a non-measuring
// sector has no points, D3, and its times say nothing about the measurement).
const SectorBlock* first_with_points(const Profile& profile) {
  for (const SectorBlock& sector : profile.sectors) {
    if (!sector.points.empty()) return &sector;
  }
  return nullptr;
}

std::string ms_figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", value);
  std::string out = text;
  while (out.back() == '0') out.pop_back();
  if (out.back() == '.') out.pop_back();
  return out;
}

}  // namespace

base::Expected<RevolutionStep, std::string> check_revolution_step(const Profile& previous, const Profile& current,
                                                                   std::uint16_t speed_hz, std::uint64_t link_lost) {
  RevolutionStep step;
  const std::string pair = "PROFILESENT " + std::to_string(previous.profile_sent) + " -> " +
                           std::to_string(current.profile_sent);
  const auto sent_step = static_cast<std::uint16_t>(current.profile_sent - previous.profile_sent);
  if (has_field(previous, profile_bits::kProfileSent) && has_field(current, profile_bits::kProfileSent) &&
      sent_step != 1 && !(sent_step > 1 && sent_step - 1u <= link_lost)) {
    return base::Unexpected(pair + ": not consecutive (spec 3.5: one more per profile sent, D10)");
  }
  if (!has_field(previous, profile_bits::kProfileCount) || !has_field(current, profile_bits::kProfileCount)) return step;
  step.counted = static_cast<std::uint16_t>(current.profile_count - previous.profile_count);
  if (step.counted == 0) {
    return base::Unexpected(pair + ": PROFILECOUNT stayed " + std::to_string(current.profile_count) +
                            " (one revolution per profile, spec 3.5)");
  }
  const SectorBlock* before = first_with_points(previous);
  const SectorBlock* after = first_with_points(current);
  if (!has_field(previous, profile_bits::kTStart) || !has_field(current, profile_bits::kTStart) || before == nullptr ||
      after == nullptr || before->sector_num != after->sector_num) {
    return step;
  }
  step.t_start_delta_ms = static_cast<std::uint16_t>(after->t_start_ms - before->t_start_ms);  // 16-bit wrap
  const double period_ms = 1000.0 / speed_hz;
  const double want_ms = step.counted * period_ms;
  if (std::abs(*step.t_start_delta_ms - want_ms) > 1.0) {
    return base::Unexpected(pair + ": TSTART advanced " + std::to_string(*step.t_start_delta_ms) +
                            " ms for a PROFILECOUNT advance of " + std::to_string(step.counted) + " (" +
                            std::to_string(previous.profile_count) + " -> " + std::to_string(current.profile_count) +
                            "); expected " + ms_figure(want_ms) + " ms +-1 at " + std::to_string(speed_hz) +
                            " Hz (device clock)");
  }
  return step;
}

std::optional<std::string> check_within_revolution(const Profile& profile, std::uint16_t speed_hz) {
  if (!has_field(profile, profile_bits::kTStart) || !has_field(profile, profile_bits::kTEnd)) return std::nullopt;
  const double period_ms = 1000.0 / speed_hz;
  for (const SectorBlock& sector : profile.sectors) {
    if (sector.points.empty()) continue;
    const auto span = static_cast<std::uint16_t>(sector.t_end_ms - sector.t_start_ms);
    if (span > period_ms + 1.0) {
      return "PROFILESENT " + std::to_string(profile.profile_sent) + " sector " + std::to_string(sector.sector_num) +
             ": TEND - TSTART = " + std::to_string(span) + " ms, longer than one revolution (" + ms_figure(period_ms) +
             " ms at " + std::to_string(speed_hz) + " Hz)";
    }
  }
  return std::nullopt;
}

std::optional<std::string> DeviceClockCheck::next(const Profile& profile, std::uint64_t link_lost) {
  last_sent_step_ = 0;
  if (!judging_) return std::nullopt;
  if (previous_ && previous_->format != profile.format) previous_.reset();  // a new stream's format
  if (auto within = check_within_revolution(profile, speed_hz_)) return within;
  std::optional<std::string> verdict;
  if (previous_) {
    last_sent_step_ = static_cast<std::uint16_t>(profile.profile_sent - previous_->profile_sent);
    auto step = check_revolution_step(*previous_, profile, speed_hz_, link_lost);
    if (!step) {
      verdict = step.error();
    } else if (step->counted > 1) {
      skipped_ += step->counted - 1u;
    }
  }
  previous_ = profile;
  return verdict;
}

}  // namespace ldoem::conformance
