// Profile to points with the geometry of D5: a return at range l, head angle theta, tilt phi
// lies at R_y(-phi) * (offset + l (cos theta, sin theta, 0)) in the pivot frame (x forward,
// y left, z up; tilt positive raises the beam plane). The caller applies T_world_pivot if it
// wants world coordinates; ldoem-scan writes the pivot frame.
#pragma once

#include <cstdint>
#include <vector>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/protocol/profile.hpp"

namespace ldoem::scan {

struct Vector3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  bool operator==(const Vector3&) const = default;
};

struct BeamPoint {
  cloud::Point3f position;  // pivot frame, metres
  float echo = 0.0F;        // ECHO-n when the format carries it, else 0
  std::uint32_t beam = 0;   // index of the point among the profile's measured points
  bool operator==(const BeamPoint&) const = default;
};

// One beam of a profile, with or without an echo.
struct Beam {
  bool has_echo = false;
  cloud::Point3f position;  // pivot frame, metres; NaN without an echo
  double range_m = 0.0;     // DISTANCE in metres; NaN without an echo
  double azimuth_deg = 0.0; // head angle (D5), (-180, 180]
  float echo = 0.0F;        // ECHO-n when the format carries it, else 0
  // The beam's time on the device's millisecond clock: TSTART + k (TEND - TSTART) / (n - 1)
  // within its sector (TSTART and TEND are the first and the last beam's times, spec 3.5), not
  // wrapped at 2^16. NaN when the format lacks TSTART or TEND.
  double device_time_ms = 0.0;
};

// Every beam of the profile in the order measured (the beam index is the position in the list).
std::vector<Beam> profile_beams(const protocol::Profile& profile, double tilt_deg, const Vector3& optical_offset_m);

// Head angle of a point in degrees, in (-180, 180]: DIRECTION-n when the format carries it,
// else STARTDIR + k * DIRSTEP (spec 3.5), wrapped (sector 0 of ldoem-scan wraps through 0).
double beam_angle_deg(const protocol::SectorBlock& sector, std::size_t point_index, bool has_direction);

// D5 for one return.
Vector3 pivot_point(double range_m, double head_angle_deg, double tilt_deg, const Vector3& optical_offset_m);

// Every point with an echo (DISTANCE 0 = no echo, D3, is skipped; its beam index still counts).
std::vector<BeamPoint> profile_to_points(const protocol::Profile& profile, double tilt_deg,
                                         const Vector3& optical_offset_m);

}  // namespace ldoem::scan
