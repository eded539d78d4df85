// The parsed scene: what the YAML file describes, in SI units, before any ODE or Embree object
// exists. The loader (scene_loader.hpp) fills it and validates every field; everything
// downstream (ray casting, sensor model, motor models, control unit defaults) reads it.
#pragma once

#include <Eigen/Geometry>

#include "ldoem/faults/fault_spec.hpp"
#include "ldoem/scene/motion.hpp"

#include <array>
#include <bitset>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace ldoem::scene {

struct Pose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// A scene's rpy_deg (roll, pitch, yaw in degrees): R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Quaterniond rotation_from_rpy_deg(const Eigen::Vector3d& rpy_deg);

// Shapes follow ODE's conventions: box by full side lengths, cylinder and capsule along the
// local z axis, plane as n . p = offset in world coordinates (planes are not placeable in ODE).
struct Box { Eigen::Vector3d size_m; };
struct Sphere { double radius_m; };
struct Cylinder { double radius_m; double length_m; };
struct Capsule { double radius_m; double length_m; };
struct Plane { Eigen::Vector3d normal; double offset_m; };
struct Mesh {
  std::string path;  // as written in the scene, resolved relative to the scene file
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  // Filled by the loader (assimp): metres in the object's frame, scale already applied.
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};
using Shape = std::variant<Box, Sphere, Cylinder, Capsule, Plane, Mesh>;

struct SceneObject {
  std::string name;
  Shape shape;
  Pose pose;                 // ignored for planes
  double reflectance = 0.8;  // Lambertian albedo r in [0, 1] (D6)
  // D12: at most one of the two; neither means the object never moves.
  std::optional<Motion> motion;      // kinematic: constant velocity and spin, or waypoints
  std::optional<Dynamics> dynamics;  // a rigid body on ODE
  // Retro-reflective sheeting sends light back towards its source instead of into the
  // hemisphere: it returns kRetroReflectiveGain times what a Lambertian target of the same r
  // would (docs/sensor-model.md). Casters report optical_reflectance(), not `reflectance`.
  bool retroreflective = false;

  bool moves() const { return motion.has_value() || dynamics.has_value(); }
};

// Coefficient of retroreflection of common sheeting (~100 cd/(lx m^2) for white class I at small
// observation angles) over a white Lambertian target's 1/pi cd/(lx m^2): about 300.
inline constexpr double kRetroReflectiveGain = 300.0;

// The reflectance the optics see: r, or r times the retro-reflective gain.
inline double optical_reflectance(const SceneObject& object) {
  return object.retroreflective ? object.reflectance * kRetroReflectiveGain : object.reflectance;
}

// How ECHO is computed from I_rs. linear: D6's min(65535, round(1000 I/I_min)), saturating at
// 65.5 times the threshold; log: round(1000 + kLogEchoPerDecade log10(I/I_min)), which covers
// 8 decades before it saturates (docs/sensor-model.md).
enum class EchoScale : std::uint8_t { linear, log };

// D6: the paper's optics. l_max = 63.1 m * sqrt(r cos alpha) with the defaults.
struct OpticsConfig {
  double emitted_intensity = 1.0;          // I0
  double receiver_diameter_m = 0.04;       // d
  double min_irradiance = 0.00016;         // I_rs_min (dropout threshold)
  // Chosen by the loader so that l_max(r=1) = max_range_at_full_reflectance_m (optics.hpp);
  // the default already agrees with the defaults above: 8 pi I_rs_min L^2 / (I0 d^2).
  double calibration = 0.00016 * 63.1 * 63.1 * 8.0 * std::numbers::pi / (1.0 * 0.04 * 0.04);
  double max_range_at_full_reflectance_m = 63.1;
  EchoScale echo_scale = EchoScale::linear;
};

struct NoiseConfig {
  double sigma_m = 0.0015;  // D6 default
  double mean_m = 0.0;
};

// D13 waveform: how the receiver turns the summed pulses into one echo.
enum class EchoDetection : std::uint8_t { first, strongest, last };
struct WaveformConfig {
  // Full width at half maximum of the emitted (Gaussian) pulse. SICK publishes none for the
  // LD-OEM; 4 ns is typical of the 905 nm pulsed laser diodes such scanners use
  // (docs/sensor-model.md).
  double pulse_width_s = 4.0e-9;
  // Detection threshold as a multiple of I_rs_min (D6): 1 keeps D6's dropout range.
  double threshold_factor = 1.0;
  EchoDetection detection = EchoDetection::first;
};

// D13 snr_noise: the receiver's noise floor, as the SNR at which the threshold sits.
struct SnrNoiseConfig {
  // I_rs_min over the noise's standard deviation: a threshold at 5 sigma of the noise gives
  // about one false alarm in 3.5 million samples (docs/sensor-model.md).
  double threshold_snr = 5.0;
};

// atmosphere: two-way Beer-Lambert extinction from the meteorological visibility (Koschmieder:
// extinction = 3.912 / V), and optionally fog's own near returns.
struct AtmosphereConfig {
  double visibility_m = 1000.0;
  // Fog's own backscatter as a false near echo (needs waveform): it peaks where the receiver's
  // field of view first fully overlaps the beam, nearer the fog is hidden from the receiver.
  bool fog_returns = false;
  double fog_overlap_m = 1.0;
};


// The measuring head (the LD's own spinning mirror motor): spin-up per D7.
struct HeadConfig {
  double inertia_kg_m2 = 2.0e-4;
  double drive_torque_n_m = 6.3e-3;   // default gives 0 -> 10 Hz in about 2 s
  double friction_n_m_s = 0.0;        // viscous friction
  double ripple_fraction = 0.001;     // head_dynamics speed ripple (relative amplitude)
  double ripple_frequency_hz = 1.0;
};

// The tilt stepper and its 20:1 worm gear (D8, D9 motor_dynamics).
struct TiltMotorConfig {
  double step_angle_deg = 1.8;
  double gear_ratio = 20.0;
  double torque_constant_n_m_per_a = 0.3;     // k_t
  double back_emf_v_s_per_rad = 0.3;          // k_v
  double winding_resistance_ohm = 2.0;        // R
  double supply_voltage_v = 12.0;             // V
  double rotor_inertia_kg_m2 = 5.0e-5;
  double load_inertia_kg_m2 = 0.05;           // plate + LD about the tilt axis
  double world_step_s = 1.0e-3;               // ODE step for motor_dynamics
  double min_tilt_deg = -90.0;
  double max_tilt_deg = 90.0;
};

struct SectorDefault {
  std::uint16_t function = 0;     // spec 3.6 function code
  std::uint16_t stop_ticks = 0;   // 1/16 deg
};

// D4: what the emulated flash holds at first power-up.
struct FlashDefaults {
  std::uint16_t sensor_id = 1;
  std::uint16_t motor_speed_hz = 10;
  std::uint16_t angle_step_ticks = 4;
  std::array<SectorDefault, 8> sectors{{{3, 2160}, {1, 3600}}};
  std::array<std::uint8_t, 4> ip_address{192, 168, 1, 10};
  std::array<std::uint8_t, 4> subnet_mask{255, 255, 255, 0};
  std::array<std::uint8_t, 4> gateway{192, 168, 1, 1};
  std::uint16_t can_request_id = 0x6C0;   // D1
  std::uint16_t can_response_id = 0x6C1;  // D1
};

// The longest identification text: its reply (`81 01` + text) is then exactly the largest
// telegram payload, 5816 bytes (D3, protocol::kMaxTelegramPayload). Issue 27 D14.
inline constexpr std::size_t kMaxIdentificationTextBytes = 5816 - 2;

// D3: GET_IDENTIFICATION texts, indexed by the item numbers of spec 3.3.
struct Identification {
  std::string sensor_part_number = "0000000";
  std::string sensor_name = "LD-OEM1000";
  std::string sensor_version = "0000000";
  std::string sensor_serial_number = "0000000";
  std::string edm_serial_number = "0000000";
  std::string firmware_part_number = "0000000";
  std::string firmware_name = "ldoem-emud";
  std::string firmware_version = LDOEM_VERSION;
  std::string application_part_number = "0000000";
  std::string application_name = "0000000";
  std::string application_version = "0000000";
};

// Issue 15: the LD-OEM's head as the other scanners of a `scanners:` scene see it, a cylinder
// about the pivot's z axis, centred on the pivot. The spec, D1..D13 and the docs give no size for
// the head; the defaults are an assumption (docs/scenes.md "Several scanners"), per scanner.
struct HousingConfig {
  double radius_m = 0.06;
  double height_m = 0.16;
  double reflectance = 0.3;  // a dark grey housing (Lambertian r, D6)
};

struct ScannerConfig {
  Pose pivot_pose;                                           // T_world_pivot (D5)
  std::optional<Motion> pivot_motion;  // D12: the platform carrying the scanner moves
  Eigen::Vector3d optical_offset_m = Eigen::Vector3d::Zero();  // optical centre from the pivot
  double min_range_m = 0.9;   // D_min (D6)
  double max_range_m = 30.0;  // D_max, <= 250 m (the LD-OEM's measuring range)
  double beam_divergence_rad = 0.0025;  // full angle, used by mixed_pixels
  int mixed_pixel_subrays = 7;          // 1, 7, 19, 37 (hexagonal rings)
  OpticsConfig optics;
  NoiseConfig noise;
  WaveformConfig waveform;
  SnrNoiseConfig snr_noise;
  AtmosphereConfig atmosphere;
  HeadConfig head;
  TiltMotorConfig tilt_motor;
  FlashDefaults flash;
  Identification identification;
  // D11 power_cycle: seconds from power-on to serving hosts again, [0, 60] (docs/decisions-local.md
  // L-faults-5: the LD-OEM's boot time is unpublished).
  double boot_s = 1.0;
  HousingConfig housing;  // only built when the scene has two scanners or more
};

// D9: the effects a scene may name. Nothing else is simulated.
enum class Effect : std::uint8_t {
  noise, intensity, incidence, mixed_pixels, motor_dynamics, head_dynamics, sweep_motion, bus_timing,
  waveform, snr_noise, atmosphere,  // D13
};
inline constexpr std::size_t kEffectCount = 11;

class EffectSet {
 public:
  bool has(Effect effect) const { return bits_.test(static_cast<std::size_t>(effect)); }
  void add(Effect effect) { bits_.set(static_cast<std::size_t>(effect)); }
  bool empty() const { return bits_.none(); }

 private:
  std::bitset<kEffectCount> bits_;
};

// Where hosts reach one scanner of a `scanners:` scene: the command line's per-device options,
// written in the scene in the endpoint grammar (docs/endpoints.md, docs/scenes.md "Several
// scanners").
struct TcpEndpointConfig {
  std::string address;
  std::uint16_t port = 0;  // 0: any free port
};
struct LptEndpointConfig {
  bool gpio = false;   // false: a pty symlinked at `target`; true: the gpio chip `target`
  std::string target;
};
struct ScannerEndpoints {
  std::optional<TcpEndpointConfig> tcp;
  // The scanner's CAN identifiers (request, response); else its flash's (D1). `can_interface`
  // is the bus they are on (`can: can:IF:REQ:RESP`); it must be the daemon's --can.
  std::optional<std::array<std::uint16_t, 2>> can_ids;
  std::string can_interface;
  std::optional<std::string> serial_pty;  // symlink path of the serial pty
  std::optional<LptEndpointConfig> lpt;
};

// One entry of `scanners:`: its own name, configuration, effects (the scene's unless it names
// its own), flash file and endpoints.
struct ScannerEntry {
  std::string name;
  ScannerConfig config;
  EffectSet effects;
  std::optional<std::string> flash_file;  // as written; relative to the scene's folder
  ScannerEndpoints endpoints;
};

// More scanners than this in one scene is an error (each is a device with its own endpoints).
inline constexpr std::size_t kMaxSceneScanners = 1024;

struct Scene {
  std::string source_path;
  std::vector<SceneObject> objects;
  ScannerConfig scanner;
  EffectSet effects;
  std::uint64_t seed = 1;
  WorldConfig world;  // D12: used only when something moves
  // D11: faults the scene injects (empty: none, and the daemon builds no fault machinery).
  std::vector<faults::FaultSpec> faults;
  // Issue 15: the `scanners:` list. Empty for a one-scanner scene (`scanner:`); otherwise
  // `scanner` and `effects` above are its first entry's.
  std::vector<ScannerEntry> scanners;

  std::size_t scanner_count() const { return scanners.empty() ? 1 : scanners.size(); }

  // D12 effects on demand: false means the scene builds no per-beam time machinery.
  bool moves() const {
    if (scanner.pivot_motion) return true;
    for (const ScannerEntry& entry : scanners) {
      if (entry.config.pivot_motion) return true;
    }
    for (const SceneObject& object : objects) {
      if (object.moves()) return true;
    }
    return false;
  }
};

}  // namespace ldoem::scene
