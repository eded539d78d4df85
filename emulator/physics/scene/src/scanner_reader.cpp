#include "scanner_reader.hpp"

#include "ldoem/base/device_constants.hpp"
#include "ldoem/scene/optics.hpp"
#include "motion_reader.hpp"
#include "pose_reader.hpp"

#include <charconv>

namespace ldoem::scene::detail {
namespace {

// The LD-OEM measures up to 250 m (SICK's product information); the DISTANCE word (1/256 m)
// could carry 255.99 m, but the device never reports beyond its range.
constexpr double kDeviceMaxRange_m = 250.0;
// Pulse widths outside this window are not a pulsed time-of-flight laser diode's.
constexpr double kMinPulseWidth_s = 1e-10;
constexpr double kMaxPulseWidth_s = 1e-7;
constexpr double kMaxBeamDivergence_rad = 0.1;
// D11 power_cycle: the longest boot a scene may ask for (docs/decisions-local.md L-faults-5).
constexpr double kMaxBootTime_s = 60.0;
constexpr std::uint64_t kMaxCanId = 0x7FF;      // 11-bit identifiers (D1)
constexpr std::uint64_t kMaxSectorFunction = 4;   // spec 3.6: 0..4

void read_optics(const std::string& file, const YAML::Node& node, const std::string& path,
                 OpticsConfig& optics) {
  MapReader map(file, node, path);
  read_field(map, "emitted_intensity", optics.emitted_intensity, Constraint::positive);
  read_field(map, "receiver_diameter_m", optics.receiver_diameter_m, Constraint::positive);
  read_field(map, "min_irradiance", optics.min_irradiance, Constraint::positive);
  read_field(map, "max_range_at_full_reflectance_m", optics.max_range_at_full_reflectance_m,
             Constraint::positive);
  read_field(map, "calibration", optics.calibration, Constraint::positive);
  std::string scale = "linear";
  read_field(map, "echo_scale", scale);
  if (scale != "linear" && scale != "log") {
    fail(file, SceneErrorKind::out_of_range, *map.get("echo_scale"), map.child_path("echo_scale"),
         "must be linear (D6) or log");
  }
  optics.echo_scale = scale == "log" ? EchoScale::log : EchoScale::linear;
  if (map.has("calibration") && map.has("max_range_at_full_reflectance_m")) {
    fail(file, SceneErrorKind::conflicting_keys, node, map.child_path("calibration"),
         "give either calibration or max_range_at_full_reflectance_m, not both");
  }
  map.finish();
}

void read_noise(const std::string& file, const YAML::Node& node, const std::string& path,
                NoiseConfig& noise) {
  MapReader map(file, node, path);
  read_field(map, "sigma_m", noise.sigma_m, Constraint::non_negative);
  read_field(map, "mean_m", noise.mean_m);
  map.finish();
}

void read_waveform(const std::string& file, const YAML::Node& node, const std::string& path,
                   WaveformConfig& waveform) {
  MapReader map(file, node, path);
  read_field(map, "pulse_width_s", waveform.pulse_width_s, Constraint::positive);
  if (waveform.pulse_width_s < kMinPulseWidth_s || waveform.pulse_width_s > kMaxPulseWidth_s) {
    fail(file, SceneErrorKind::out_of_range, *map.get("pulse_width_s"), map.child_path("pulse_width_s"),
         "must be between 1e-10 and 1e-7 s");
  }
  read_field(map, "threshold_factor", waveform.threshold_factor, Constraint::positive);
  if (waveform.threshold_factor < 1.0) {
    fail(file, SceneErrorKind::out_of_range, *map.get("threshold_factor"), map.child_path("threshold_factor"),
         "must be >= 1 (D6: I_rs_min is the weakest return the LD detects)");
  }
  std::string detection = "first";
  read_field(map, "detection", detection);
  if (detection == "first") {
    waveform.detection = EchoDetection::first;
  } else if (detection == "strongest") {
    waveform.detection = EchoDetection::strongest;
  } else if (detection == "last") {
    waveform.detection = EchoDetection::last;
  } else {
    fail(file, SceneErrorKind::out_of_range, *map.get("detection"), map.child_path("detection"),
         "must be first, strongest or last");
  }
  map.finish();
}

void read_snr_noise(const std::string& file, const YAML::Node& node, const std::string& path,
                    SnrNoiseConfig& snr) {
  MapReader map(file, node, path);
  read_field(map, "threshold_snr", snr.threshold_snr, Constraint::positive);
  map.finish();
}

void read_atmosphere(const std::string& file, const YAML::Node& node, const std::string& path,
                     AtmosphereConfig& atmosphere) {
  MapReader map(file, node, path);
  read_field(map, "visibility_m", atmosphere.visibility_m, Constraint::positive);
  read_field(map, "fog_returns", atmosphere.fog_returns);
  read_field(map, "fog_overlap_m", atmosphere.fog_overlap_m, Constraint::positive);
  map.finish();
}

void read_head(const std::string& file, const YAML::Node& node, const std::string& path,
               HeadConfig& head) {
  MapReader map(file, node, path);
  read_field(map, "inertia_kg_m2", head.inertia_kg_m2, Constraint::positive);
  read_field(map, "drive_torque_n_m", head.drive_torque_n_m, Constraint::positive);
  read_field(map, "friction_n_m_s", head.friction_n_m_s, Constraint::non_negative);
  read_field(map, "ripple_fraction", head.ripple_fraction, Constraint::below_one);
  read_field(map, "ripple_frequency_hz", head.ripple_frequency_hz, Constraint::non_negative);
  map.finish();
}

void read_tilt_motor(const std::string& file, const YAML::Node& node, const std::string& path,
                     TiltMotorConfig& motor) {
  MapReader map(file, node, path);
  read_field(map, "step_angle_deg", motor.step_angle_deg, Constraint::positive);
  read_field(map, "gear_ratio", motor.gear_ratio, Constraint::positive);
  read_field(map, "torque_constant_n_m_per_a", motor.torque_constant_n_m_per_a, Constraint::positive);
  read_field(map, "back_emf_v_s_per_rad", motor.back_emf_v_s_per_rad, Constraint::non_negative);
  read_field(map, "winding_resistance_ohm", motor.winding_resistance_ohm, Constraint::positive);
  read_field(map, "supply_voltage_v", motor.supply_voltage_v, Constraint::positive);
  read_field(map, "rotor_inertia_kg_m2", motor.rotor_inertia_kg_m2, Constraint::positive);
  read_field(map, "load_inertia_kg_m2", motor.load_inertia_kg_m2, Constraint::non_negative);
  read_step(map, "world_step_s", motor.world_step_s);  // issue 27 D5: 1e-9 stalled the loop
  read_field(map, "min_tilt_deg", motor.min_tilt_deg);
  read_field(map, "max_tilt_deg", motor.max_tilt_deg);
  if (!(motor.min_tilt_deg >= -180.0 && motor.max_tilt_deg <= 180.0 &&
        motor.min_tilt_deg < motor.max_tilt_deg)) {
    fail(file, SceneErrorKind::out_of_range, node, map.child_path("max_tilt_deg"),
         "need -180 <= min_tilt_deg < max_tilt_deg <= 180");
  }
  map.finish();
}

std::array<std::uint8_t, 4> read_ipv4(const std::string& file, const YAML::Node& node,
                                      const std::string& path) {
  const std::string text = read_string(file, node, path);
  std::array<std::uint8_t, 4> octets{};
  const char* cursor = text.data();
  const char* const end = text.data() + text.size();
  for (std::size_t i = 0; i < 4; ++i) {
    unsigned value = 256;
    const auto [next, status] = std::from_chars(cursor, end, value);
    const bool separator_ok = (i == 3) ? next == end : (next != end && *next == '.');
    if (status != std::errc() || value > 255 || !separator_ok) {
      fail(file, SceneErrorKind::wrong_type, node, path, "must be a dotted IPv4 address");
    }
    octets[i] = static_cast<std::uint8_t>(value);
    cursor = next + 1;
  }
  return octets;
}

void read_sectors(const std::string& file, const YAML::Node& node, const std::string& path,
                  std::array<SectorDefault, 8>& sectors) {
  require_sequence(file, node, path);
  if (node.size() > sectors.size()) {
    fail(file, SceneErrorKind::out_of_range, node, path, "at most 8 sectors (spec 3.6)");
  }
  sectors = {};  // a given table replaces the default one; the rest is "not initialised"
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string sector_path = path + "[" + std::to_string(i) + "]";
    MapReader map(file, node[i], sector_path);
    read_field(map, "function", sectors[i].function, 0, kMaxSectorFunction);
    read_field(map, "stop_ticks", sectors[i].stop_ticks, 0, 0xFFFF);
    if (sectors[i].function != 0 && sectors[i].stop_ticks > std::uint64_t{base::kTicksPerTurn}) {
      fail(file, SceneErrorKind::out_of_range, node[i], map.child_path("stop_ticks"),
           "an initialised sector stops at <= 5760 (360 deg, spec 3.6)");
    }
    map.finish();
  }
}

void read_flash(const std::string& file, const YAML::Node& node, const std::string& path,
                FlashDefaults& flash) {
  MapReader map(file, node, path);
  read_field(map, "sensor_id", flash.sensor_id, 1, 254);
  read_field(map, "motor_speed_hz", flash.motor_speed_hz, base::kMinMotorSpeedHz, base::kMaxMotorSpeedHz);
  read_field(map, "angle_step_ticks", flash.angle_step_ticks, 1, std::uint64_t{base::kTicksPerTurn});
  if (auto sectors = map.get("sectors")) read_sectors(file, *sectors, map.child_path("sectors"), flash.sectors);
  if (auto ip = map.get("ip_address")) flash.ip_address = read_ipv4(file, *ip, map.child_path("ip_address"));
  if (auto mask = map.get("subnet_mask")) flash.subnet_mask = read_ipv4(file, *mask, map.child_path("subnet_mask"));
  if (auto gateway = map.get("gateway")) flash.gateway = read_ipv4(file, *gateway, map.child_path("gateway"));
  read_field(map, "can_request_id", flash.can_request_id, 0, kMaxCanId);
  read_field(map, "can_response_id", flash.can_response_id, 0, kMaxCanId);
  if (flash.can_request_id == flash.can_response_id) {
    fail(file, SceneErrorKind::conflicting_keys, node, map.child_path("can_response_id"),
         "must differ from can_request_id (D1)");
  }
  map.finish();
}

// Issue 27 D14: a GET_IDENTIFICATION reply is `81 01` and the text, and no telegram's payload
// may exceed 5816 bytes (D3; some hosts crash beyond it, and TCP drops the connection): each
// text is bounded here, before the device can serve it.
void read_identification_text(MapReader& map, std::string_view key, std::string& out) {
  read_field(map, key, out);
  if (out.size() > kMaxIdentificationTextBytes) {
    fail(map.file(), SceneErrorKind::out_of_range, map.get(key).value_or(map.node()), map.child_path(key),
         "is " + std::to_string(out.size()) + " bytes long; at most " + std::to_string(kMaxIdentificationTextBytes) +
             " (the reply's payload may not exceed 5816 bytes, D3)");
  }
}

void read_identification(const std::string& file, const YAML::Node& node, const std::string& path,
                         Identification& id) {
  MapReader map(file, node, path);
  read_identification_text(map, "sensor_part_number", id.sensor_part_number);
  read_identification_text(map, "sensor_name", id.sensor_name);
  read_identification_text(map, "sensor_version", id.sensor_version);
  read_identification_text(map, "sensor_serial_number", id.sensor_serial_number);
  read_identification_text(map, "edm_serial_number", id.edm_serial_number);
  read_identification_text(map, "firmware_part_number", id.firmware_part_number);
  read_identification_text(map, "firmware_name", id.firmware_name);
  read_identification_text(map, "firmware_version", id.firmware_version);
  read_identification_text(map, "application_part_number", id.application_part_number);
  read_identification_text(map, "application_name", id.application_name);
  read_identification_text(map, "application_version", id.application_version);
  map.finish();
}

void read_ranges(MapReader& map, ScannerConfig& scanner) {
  read_field(map, "min_range_m", scanner.min_range_m, Constraint::positive);
  read_field(map, "max_range_m", scanner.max_range_m, Constraint::positive);
  if (scanner.max_range_m > kDeviceMaxRange_m) {
    fail(map.file(), SceneErrorKind::out_of_range, *map.get("max_range_m"),
         map.child_path("max_range_m"), "must be <= 250 m (the LD-OEM's measuring range)");
  }
  if (!(scanner.min_range_m < scanner.max_range_m)) {
    fail(map.file(), SceneErrorKind::out_of_range, map.node(), map.child_path("min_range_m"),
         "must be below max_range_m");
  }
  read_field(map, "beam_divergence_rad", scanner.beam_divergence_rad, Constraint::non_negative);
  if (scanner.beam_divergence_rad >= kMaxBeamDivergence_rad) {
    fail(map.file(), SceneErrorKind::out_of_range, *map.get("beam_divergence_rad"),
         map.child_path("beam_divergence_rad"), "must be below 0.1 rad");
  }
  read_field(map, "mixed_pixel_subrays", scanner.mixed_pixel_subrays, 1, 37);
  const int subrays = scanner.mixed_pixel_subrays;
  if (subrays != 1 && subrays != 7 && subrays != 19 && subrays != 37) {
    fail(map.file(), SceneErrorKind::out_of_range, *map.get("mixed_pixel_subrays"),
         map.child_path("mixed_pixel_subrays"), "must be 1, 7, 19 or 37 (hexagonal rings)");
  }
}

void read_housing(const std::string& file, const YAML::Node& node, const std::string& path,
                  HousingConfig& housing) {
  MapReader map(file, node, path);
  read_field(map, "radius_m", housing.radius_m, Constraint::positive);
  read_field(map, "height_m", housing.height_m, Constraint::positive);
  read_field(map, "reflectance", housing.reflectance, Constraint::unit_interval);
  map.finish();
}

}  // namespace

ScannerConfig read_scanner(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  ScannerConfig scanner = read_scanner_fields(map);
  map.finish();
  return scanner;
}

ScannerConfig read_scanner_fields(MapReader& map) {
  ScannerConfig scanner;
  const std::string& file = map.file();
  if (auto pose = map.get("pivot_pose")) scanner.pivot_pose = read_pose(file, *pose, map.child_path("pivot_pose"));
  if (auto motion = map.get("pivot_motion")) {  // D12: the platform carrying the scanner
    scanner.pivot_motion = read_motion(file, *motion, map.child_path("pivot_motion"));
    if (std::holds_alternative<Waypoints>(*scanner.pivot_motion)) {
      if (map.has("pivot_pose")) {
        fail(file, SceneErrorKind::conflicting_keys, *map.get("pivot_pose"), map.child_path("pivot_pose"),
             "pivot_motion waypoints give absolute poses; drop pivot_pose or use velocities");
      }
      scanner.pivot_pose = pose_at(*scanner.pivot_motion, scanner.pivot_pose, 0.0);
    }
  }
  read_field(map, "optical_offset_m", scanner.optical_offset_m);
  read_ranges(map, scanner);
  read_field(map, "boot_s", scanner.boot_s, Constraint::non_negative);
  if (scanner.boot_s > kMaxBootTime_s) {
    fail(file, SceneErrorKind::out_of_range, *map.get("boot_s"), map.child_path("boot_s"), "must be <= 60 s");
  }
  const bool calibration_given = [&] {
    if (auto optics = map.get("optics")) {
      read_optics(file, *optics, map.child_path("optics"), scanner.optics);
      return optics->IsMap() && optics->operator[]("calibration").IsDefined();
    }
    return false;
  }();
  // D6: one constant reproduces l_max = L sqrt(r cos alpha); a given calibration wins and L
  // is then derived from it, so the two fields always agree.
  if (calibration_given) {
    scanner.optics.max_range_at_full_reflectance_m = max_range_at_full_reflectance(scanner.optics);
  } else {
    scanner.optics.calibration =
        calibration_for_max_range(scanner.optics, scanner.optics.max_range_at_full_reflectance_m);
  }
  if (auto noise = map.get("noise")) read_noise(file, *noise, map.child_path("noise"), scanner.noise);
  if (auto waveform = map.get("waveform")) read_waveform(file, *waveform, map.child_path("waveform"), scanner.waveform);
  if (auto snr = map.get("snr_noise")) read_snr_noise(file, *snr, map.child_path("snr_noise"), scanner.snr_noise);
  if (auto atmosphere = map.get("atmosphere")) {
    read_atmosphere(file, *atmosphere, map.child_path("atmosphere"), scanner.atmosphere);
  }
  if (auto head = map.get("head")) read_head(file, *head, map.child_path("head"), scanner.head);
  if (auto motor = map.get("tilt_motor")) read_tilt_motor(file, *motor, map.child_path("tilt_motor"), scanner.tilt_motor);
  if (auto flash = map.get("flash")) read_flash(file, *flash, map.child_path("flash"), scanner.flash);
  if (auto id = map.get("identification")) {
    read_identification(file, *id, map.child_path("identification"), scanner.identification);
  }
  if (auto housing = map.get("housing")) read_housing(file, *housing, map.child_path("housing"), scanner.housing);
  return scanner;
}

}  // namespace ldoem::scene::detail
