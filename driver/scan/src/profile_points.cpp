#include "ldoem/scan/profile_points.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "ldoem/scan/scan_plan.hpp"

namespace ldoem::scan {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
// Spec 2.3: DISTANCE is in 1/256 m.
constexpr double kMetresPerDistanceUnit = 1.0 / 256.0;

}  // namespace

double beam_angle_deg(const protocol::SectorBlock& sector, std::size_t point_index, bool has_direction) {
  const std::int64_t ticks = has_direction
                                 ? sector.points[point_index].direction_ticks
                                 : static_cast<std::int64_t>(sector.start_dir_ticks) +
                                       static_cast<std::int64_t>(point_index) * sector.dir_step_ticks;
  std::int64_t wrapped = ticks % kTicksPerTurn;
  if (wrapped > static_cast<std::int64_t>(kTicksPerTurn / 2)) {
    wrapped -= kTicksPerTurn;
  }
  return static_cast<double>(wrapped) / kTicksPerDegree;
}

Vector3 pivot_point(double range_m, double head_angle_deg, double tilt_deg, const Vector3& optical_offset_m) {
  const double theta = head_angle_deg * kRadiansPerDegree;
  const double phi = tilt_deg * kRadiansPerDegree;
  const Vector3 head{optical_offset_m.x + range_m * std::cos(theta), optical_offset_m.y + range_m * std::sin(theta),
                     optical_offset_m.z};
  // R_y(-phi): x' = x cos phi - z sin phi, z' = x sin phi + z cos phi.
  return {head.x * std::cos(phi) - head.z * std::sin(phi), head.y, head.x * std::sin(phi) + head.z * std::cos(phi)};
}

std::vector<Beam> profile_beams(const protocol::Profile& profile, double tilt_deg, const Vector3& optical_offset_m) {
  const bool has_direction = (profile.format & protocol::profile_bits::kDirection) != 0;
  const bool has_distance = (profile.format & protocol::profile_bits::kDistance) != 0;
  const bool has_echo = (profile.format & protocol::profile_bits::kEcho) != 0;
  const bool has_times = (profile.format & protocol::profile_bits::kTStart) != 0 &&
                         (profile.format & protocol::profile_bits::kTEnd) != 0;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  std::vector<Beam> beams;
  for (const protocol::SectorBlock& sector : profile.sectors) {
    // The sector's duration modulo 2^16 ms: TEND may have wrapped past TSTART.
    const double duration_ms = static_cast<std::uint16_t>(sector.t_end_ms - sector.t_start_ms);
    const std::size_t count = sector.points.size();
    for (std::size_t k = 0; k < count; ++k) {
      const protocol::ProfilePoint& point = sector.points[k];
      Beam beam;
      beam.azimuth_deg = beam_angle_deg(sector, k, has_direction);
      beam.device_time_ms = has_times ? sector.t_start_ms + (count > 1 ? duration_ms * static_cast<double>(k) /
                                                                              static_cast<double>(count - 1)
                                                                        : 0.0)
                                      : kNaN;
      beam.has_echo = has_distance && point.distance_q8_m != 0;
      if (beam.has_echo) {
        beam.range_m = point.distance_q8_m * kMetresPerDistanceUnit;
        const Vector3 position = pivot_point(beam.range_m, beam.azimuth_deg, tilt_deg, optical_offset_m);
        beam.position = {static_cast<float>(position.x), static_cast<float>(position.y),
                         static_cast<float>(position.z)};
        beam.echo = has_echo ? static_cast<float>(point.echo) : 0.0F;
      } else {
        beam.range_m = kNaN;
        beam.position = {kNaNf, kNaNf, kNaNf};
      }
      beams.push_back(beam);
    }
  }
  return beams;
}

std::vector<BeamPoint> profile_to_points(const protocol::Profile& profile, double tilt_deg,
                                         const Vector3& optical_offset_m) {
  std::vector<BeamPoint> points;
  std::uint32_t index = 0;
  for (const Beam& beam : profile_beams(profile, tilt_deg, optical_offset_m)) {
    if (beam.has_echo) points.push_back(BeamPoint{beam.position, beam.echo, index});
    ++index;
  }
  return points;
}

}  // namespace ldoem::scan
