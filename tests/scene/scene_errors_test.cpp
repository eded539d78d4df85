// Bad scenes: each gives one typed error naming file:line:column and the key path.
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

namespace ldoem::scene {
namespace {

struct BadScene {
  const char* title;
  const char* yaml;
  SceneErrorKind kind;
  const char* key_path;
  int line;    // 1-based, 0 = not checked
  int column;  // 1-based, 0 = not checked
};

// Line/column point at the offending node (or key, for unknown keys).
const BadScene kBadScenes[] = {
    {"unknown top-level key", "objcts: []", SceneErrorKind::unknown_key, "objcts", 1, 1},
    {"unknown object key", "objects:\n  - {box: {size_m: [1, 1, 1]}, colour: red}", SceneErrorKind::unknown_key,
     "objects[0].colour", 2, 32},
    {"unknown scanner key", "scanner:\n  min_rang_m: 1", SceneErrorKind::unknown_key, "scanner.min_rang_m", 2, 3},
    {"unknown nested key", "scanner: {optics: {diameter: 1}}", SceneErrorKind::unknown_key,
     "scanner.optics.diameter", 1, 20},
    {"duplicate key", "seed: 1\nseed: 2", SceneErrorKind::duplicate_key, "seed", 2, 1},
    {"text for a number", "scanner: {min_range_m: far}", SceneErrorKind::wrong_type, "scanner.min_range_m", 1, 24},
    {"map for a number", "objects: [{sphere: {radius_m: {a: 1}}}]", SceneErrorKind::wrong_type,
     "objects[0].sphere.radius_m", 1, 31},
    {"objects not a list", "objects: {a: 1}", SceneErrorKind::wrong_type, "objects", 1, 10},
    {"vector of 2", "objects: [{box: {size_m: [1, 1]}}]", SceneErrorKind::wrong_type, "objects[0].box.size_m", 1, 26},
    {"NaN", "objects: [{sphere: {radius_m: .nan}}]", SceneErrorKind::not_finite, "objects[0].sphere.radius_m", 1, 31},
    {"Inf", "scanner: {noise: {mean_m: .inf}}", SceneErrorKind::not_finite, "scanner.noise.mean_m", 1, 27},
    {"-Inf in a vector", "objects: [{sphere: {radius_m: 1}, pose: {position_m: [0, -.inf, 0]}}]",
     SceneErrorKind::not_finite, "objects[0].pose.position_m[1]", 1, 58},
    {"beyond 1e9", "objects: [{sphere: {radius_m: 1}, pose: {position_m: [2e9, 0, 0]}}]", SceneErrorKind::out_of_range,
     "objects[0].pose.position_m[0]", 1, 55},
    {"negative size", "objects:\n  - box: {size_m: [1, -2, 1]}", SceneErrorKind::out_of_range,
     "objects[0].box.size_m[1]", 2, 23},
    {"zero radius", "objects: [{sphere: {radius_m: 0}}]", SceneErrorKind::out_of_range, "objects[0].sphere.radius_m", 1, 31},
    {"negative capsule length", "objects: [{capsule: {radius_m: 1, length_m: -1}}]", SceneErrorKind::out_of_range,
     "objects[0].capsule.length_m", 1, 45},
    {"reflectance above 1", "objects: [{sphere: {radius_m: 1}, reflectance: 1.5}]", SceneErrorKind::out_of_range,
     "objects[0].reflectance", 1, 48},
    {"reflectance below 0", "objects: [{sphere: {radius_m: 1}, reflectance: -0.1}]", SceneErrorKind::out_of_range,
     "objects[0].reflectance", 1, 48},
    {"zero plane normal", "objects: [{plane: {normal: [0, 0, 0]}}]", SceneErrorKind::out_of_range,
     "objects[0].plane.normal", 1, 28},
    {"zero quaternion", "objects: [{sphere: {radius_m: 1}, pose: {quaternion_wxyz: [0, 0, 0, 0]}}]",
     SceneErrorKind::out_of_range, "objects[0].pose.quaternion_wxyz", 1, 59},
    {"missing mesh file", "objects:\n  - mesh: {file: no/such/mesh.obj}", SceneErrorKind::mesh, "objects[0].mesh.file", 2, 18},
    {"unknown effect", "effects: [noise, fog]", SceneErrorKind::unknown_effect, "effects[1]", 1, 18},
    {"effect twice", "effects: [noise, noise]", SceneErrorKind::duplicate_key, "effects[1]", 1, 18},
    {"no shape", "objects: [{name: x}]", SceneErrorKind::missing_key, "objects[0]", 1, 11},
    {"two shapes", "objects: [{sphere: {radius_m: 1}, box: {size_m: [1, 1, 1]}}]", SceneErrorKind::conflicting_keys,
     "objects[0].sphere", 1, 11},
    {"missing size", "objects: [{box: {}}]", SceneErrorKind::missing_key, "objects[0].box.size_m", 1, 17},
    {"rpy and quaternion", "objects: [{sphere: {radius_m: 1}, pose: {rpy_deg: [0, 0, 0], quaternion_wxyz: [1, 0, 0, 0]}}]",
     SceneErrorKind::conflicting_keys, "objects[0].pose.quaternion_wxyz", 1, 41},
    {"pose on a plane", "objects: [{plane: {normal: [0, 0, 1]}, pose: {position_m: [0, 0, 1]}}]",
     SceneErrorKind::conflicting_keys, "objects[0].pose", 1, 46},
    {"max range beyond protocol", "scanner: {max_range_m: 300}", SceneErrorKind::out_of_range, "scanner.max_range_m", 1, 24},
    {"min range above max", "scanner: {min_range_m: 40}", SceneErrorKind::out_of_range, "scanner.min_range_m", 1, 10},
    {"boot time beyond 60 s", "scanner: {boot_s: 61}", SceneErrorKind::out_of_range, "scanner.boot_s", 1, 19},
    {"negative boot time", "scanner: {boot_s: -1}", SceneErrorKind::out_of_range, "scanner.boot_s", 1, 19},
    {"subrays not hexagonal", "scanner: {mixed_pixel_subrays: 5}", SceneErrorKind::out_of_range,
     "scanner.mixed_pixel_subrays", 1, 32},
    {"negative sigma", "scanner: {noise: {sigma_m: -0.001}}", SceneErrorKind::out_of_range, "scanner.noise.sigma_m", 1, 28},
    {"calibration and max range", "scanner: {optics: {calibration: 1, max_range_at_full_reflectance_m: 50}}",
     SceneErrorKind::conflicting_keys, "scanner.optics.calibration", 1, 19},
    {"motor speed out of range", "scanner: {flash: {motor_speed_hz: 25}}", SceneErrorKind::out_of_range,
     "scanner.flash.motor_speed_hz", 1, 35},
    {"negative integer", "seed: -1", SceneErrorKind::out_of_range, "seed", 1, 7},
    {"fractional integer", "scanner: {flash: {sensor_id: 1.5}}", SceneErrorKind::wrong_type, "scanner.flash.sensor_id", 1, 30},
    {"CAN id beyond 11 bits", "scanner: {flash: {can_request_id: 0x800}}", SceneErrorKind::out_of_range,
     "scanner.flash.can_request_id", 1, 35},
    {"bad IPv4", "scanner: {flash: {ip_address: 10.0.0.256}}", SceneErrorKind::wrong_type, "scanner.flash.ip_address", 1, 31},
    {"nine sectors", "scanner: {flash: {sectors: [{}, {}, {}, {}, {}, {}, {}, {}, {}]}}", SceneErrorKind::out_of_range,
     "scanner.flash.sectors", 1, 28},
    {"tilt limits reversed", "scanner: {tilt_motor: {min_tilt_deg: 10, max_tilt_deg: -10}}", SceneErrorKind::out_of_range,
     "scanner.tilt_motor.max_tilt_deg", 1, 23},
    {"scanner and device", "scanner: {}\ndevice: {}", SceneErrorKind::conflicting_keys, "device", 1, 1},
    {"identification not text", "device: {identification: {sensor_name: [a]}}", SceneErrorKind::wrong_type,
     "device.identification.sensor_name", 1, 40},
    {"not YAML", "objects: [\n  {box: ", SceneErrorKind::syntax, "", 0, 0},
    {"empty document", "", SceneErrorKind::wrong_type, "", 0, 0},
    {"top level is a list", "- a\n- b", SceneErrorKind::wrong_type, "", 1, 1},
};

// gtest prints the title instead of the struct's bytes.
void PrintTo(const BadScene& bad, std::ostream* out) { *out << bad.title; }

class BadSceneTest : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneTest, Load_GivesTypedErrorWithPlace) {
  const BadScene& bad = GetParam();
  const auto result = load_scene_from_string(bad.yaml, "scenes/x.yaml");
  ASSERT_FALSE(result.has_value()) << bad.title;
  const SceneError& error = result.error();
  EXPECT_EQ(error.kind, bad.kind) << bad.title << ": " << error.message();
  EXPECT_EQ(error.key_path, bad.key_path) << bad.title << ": " << error.message();
  EXPECT_EQ(error.file, "scenes/x.yaml");
  if (bad.line != 0) {
    EXPECT_EQ(error.line, bad.line) << bad.title << ": " << error.message();
    EXPECT_EQ(error.column, bad.column) << bad.title << ": " << error.message();
  }
  EXPECT_FALSE(error.detail.empty());
}

INSTANTIATE_TEST_SUITE_P(Table, BadSceneTest, ::testing::ValuesIn(kBadScenes),
                         [](const ::testing::TestParamInfo<BadScene>& info) {
                           std::string name = info.param.title;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST(SceneErrorMessage, NegativeSize_ReadsFileLineColumnPathDetail) {
  const auto result = load_scene_from_string("objects:\n  - box: {size_m: [1, -2, 1]}\n", "scenes/x.yaml");
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().message(), "scenes/x.yaml:2:23: objects[0].box.size_m[1]: must be positive");
}

TEST(SceneErrorMessage, SyntaxError_HasPosition) {
  const auto result = load_scene_from_string("a: [1, 2\nb: 3\n", "s.yaml");
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::syntax);
  EXPECT_GT(result.error().line, 0);
  EXPECT_EQ(result.error().message().rfind("s.yaml:", 0), 0u);
}

// Issue 27 D14: an identification text longer than 5814 bytes would make a reply over the
// 5816-byte payload limit; 5814 itself fits exactly.
TEST(SceneErrorMessage, IdentificationTextOverTheTelegramLimit_IsOutOfRange) {
  const std::string objects = "objects:\n  - box: {size_m: [1, 1, 1]}\n";
  const auto too_long = load_scene_from_string(
      "scanner:\n  identification:\n    firmware_name: " + std::string(5815, 'F') + "\n" + objects, "s.yaml");
  ASSERT_FALSE(too_long);
  EXPECT_EQ(too_long.error().kind, SceneErrorKind::out_of_range);
  EXPECT_NE(too_long.error().message().find("scanner.identification.firmware_name: is 5815 bytes long; at most 5814"),
            std::string::npos)
      << too_long.error().message();
  const auto longest = load_scene_from_string(
      "scanner:\n  identification:\n    firmware_name: " + std::string(5814, 'F') + "\n" + objects, "s.yaml");
  ASSERT_TRUE(longest) << longest.error().message();
  EXPECT_EQ(longest->scanner.identification.firmware_name.size(), 5814u);
}

TEST(SceneErrorKinds, EveryKind_HasAName) {
  for (int k = 0; k <= static_cast<int>(SceneErrorKind::internal); ++k) {
    EXPECT_FALSE(to_string(static_cast<SceneErrorKind>(k)).empty());
  }
  EXPECT_EQ(to_string(SceneErrorKind::unknown_effect), "unknown_effect");
}

}  // namespace
}  // namespace ldoem::scene
