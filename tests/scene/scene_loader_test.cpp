// Valid scenes: every field lands where scene.hpp says, defaults stay the defaults.
#include "ldoem/scene/optics.hpp"
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>

#include "scene_sources.hpp"

namespace ldoem::scene {
namespace {

using test::load_ok;

TEST(SceneLoader, EmptyMap_GivesDefaults) {
  const Scene scene = load_ok("{}");
  const ScannerConfig defaults;
  EXPECT_TRUE(scene.objects.empty());
  EXPECT_TRUE(scene.effects.empty());
  EXPECT_EQ(scene.seed, 1u);
  EXPECT_EQ(scene.scanner.min_range_m, defaults.min_range_m);
  EXPECT_EQ(scene.scanner.max_range_m, defaults.max_range_m);
  EXPECT_EQ(scene.scanner.noise.sigma_m, 0.0015);
  EXPECT_EQ(scene.scanner.identification.sensor_name, "LD-OEM1000");
  EXPECT_EQ(scene.scanner.flash.sectors[0].stop_ticks, 2160);
  EXPECT_EQ(scene.source_path, "test.yaml");
}

TEST(SceneLoader, DefaultCalibration_ReproducesPaperRange) {
  const Scene scene = load_ok("{}");
  EXPECT_NEAR(max_range_at_full_reflectance(scene.scanner.optics), 63.1, 1e-12);
  // The header default already agrees with what the loader computes.
  EXPECT_NEAR(OpticsConfig{}.calibration / scene.scanner.optics.calibration, 1.0, 1e-14);
}

TEST(SceneLoader, AllPrimitives_ParseWithPoses) {
  const Scene scene = load_ok(R"(
objects:
  - {name: b, box: {size_m: [1, 2, 3]}, pose: {position_m: [1, 2, 3], rpy_deg: [0, 0, 90]}, reflectance: 0.25}
  - {sphere: {radius_m: 0.5}}
  - {cylinder: {radius_m: 0.1, length_m: 2}, pose: {quaternion_wxyz: [2, 0, 0, 0]}}
  - {capsule: {radius_m: 0.1, length_m: 0}}
  - {plane: {normal: [0, 0, 2], offset_m: -1}}
)");
  ASSERT_EQ(scene.objects.size(), 5u);
  const auto& box = std::get<Box>(scene.objects[0].shape);
  EXPECT_EQ(box.size_m, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(scene.objects[0].name, "b");
  EXPECT_EQ(scene.objects[0].reflectance, 0.25);
  EXPECT_EQ(scene.objects[0].pose.position_m, Eigen::Vector3d(1, 2, 3));
  // yaw 90 deg turns +x into +y
  const Eigen::Vector3d turned = scene.objects[0].pose.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR((turned - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_EQ(scene.objects[1].name, "object1");
  EXPECT_EQ(scene.objects[1].reflectance, 0.8);
  EXPECT_EQ(std::get<Sphere>(scene.objects[1].shape).radius_m, 0.5);
  EXPECT_NEAR(scene.objects[2].pose.orientation.norm(), 1.0, 1e-15);
  EXPECT_EQ(std::get<Capsule>(scene.objects[3].shape).length_m, 0.0);
  const auto& plane = std::get<Plane>(scene.objects[4].shape);
  EXPECT_EQ(plane.normal, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(plane.offset_m, -1.0);
}

TEST(SceneLoader, RollPitchYaw_ComposeAsZYX) {
  const Scene scene = load_ok("objects: [{sphere: {radius_m: 1}, pose: {rpy_deg: [90, 90, 0]}}]");
  // R = Ry(90) Rx(90): y -> (Rx) z -> (Ry) x
  const Eigen::Vector3d y_turned = scene.objects[0].pose.orientation * Eigen::Vector3d::UnitY();
  EXPECT_NEAR((y_turned - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-15);
}

TEST(SceneLoader, ScannerSection_EveryGroupOverrides) {
  const Scene scene = load_ok(R"(
seed: 0xFFFFFFFFFFFFFFFF
effects: [noise, mixed_pixels, bus_timing]
scanner:
  pivot_pose: {position_m: [0, 0, 0.5], rpy_deg: [0, 0, 180]}
  optical_offset_m: [0.01, 0, 0.05]
  min_range_m: 0.5
  max_range_m: 100
  beam_divergence_rad: 0.003
  mixed_pixel_subrays: 19
  optics: {receiver_diameter_m: 0.05, max_range_at_full_reflectance_m: 80}
  noise: {sigma_m: 0, mean_m: 0.001}
  head: {inertia_kg_m2: 1e-4, drive_torque_n_m: 0.01, friction_n_m_s: 1e-5, ripple_fraction: 0.01, ripple_frequency_hz: 2}
  tilt_motor: {step_angle_deg: 0.9, gear_ratio: 10, min_tilt_deg: -30, max_tilt_deg: 30, world_step_s: 0.0005}
  flash:
    sensor_id: 7
    motor_speed_hz: 20
    angle_step_ticks: 8
    sectors: [{function: 3, stop_ticks: 5759}]
    ip_address: 10.0.0.2
    can_request_id: 0x100
    can_response_id: 0x101
  identification: {sensor_serial_number: "12345678", firmware_version: "9.9"}
)");
  const ScannerConfig& s = scene.scanner;
  EXPECT_EQ(scene.seed, 0xFFFFFFFFFFFFFFFFull);
  EXPECT_TRUE(scene.effects.has(Effect::noise));
  EXPECT_TRUE(scene.effects.has(Effect::mixed_pixels));
  EXPECT_TRUE(scene.effects.has(Effect::bus_timing));
  EXPECT_FALSE(scene.effects.has(Effect::intensity));
  EXPECT_EQ(s.pivot_pose.position_m.z(), 0.5);
  EXPECT_EQ(s.optical_offset_m, Eigen::Vector3d(0.01, 0, 0.05));
  EXPECT_EQ(s.min_range_m, 0.5);
  EXPECT_EQ(s.max_range_m, 100.0);
  EXPECT_EQ(s.beam_divergence_rad, 0.003);
  EXPECT_EQ(s.mixed_pixel_subrays, 19);
  EXPECT_NEAR(max_range_at_full_reflectance(s.optics), 80.0, 1e-12);
  EXPECT_EQ(s.noise.sigma_m, 0.0);
  EXPECT_EQ(s.noise.mean_m, 0.001);
  EXPECT_EQ(s.head.ripple_frequency_hz, 2.0);
  EXPECT_EQ(s.tilt_motor.step_angle_deg, 0.9);
  EXPECT_EQ(s.tilt_motor.min_tilt_deg, -30.0);
  EXPECT_EQ(s.tilt_motor.world_step_s, 0.0005);
  EXPECT_EQ(s.tilt_motor.supply_voltage_v, 12.0);  // untouched default
  EXPECT_EQ(s.flash.sensor_id, 7);
  EXPECT_EQ(s.flash.motor_speed_hz, 20);
  EXPECT_EQ(s.flash.sectors[0].function, 3);
  EXPECT_EQ(s.flash.sectors[0].stop_ticks, 5759);
  EXPECT_EQ(s.flash.sectors[1].function, 0);  // a given table replaces the default one
  EXPECT_EQ(s.flash.ip_address, (std::array<std::uint8_t, 4>{10, 0, 0, 2}));
  EXPECT_EQ(s.flash.can_request_id, 0x100);
  EXPECT_EQ(s.identification.sensor_serial_number, "12345678");
  EXPECT_EQ(s.identification.firmware_version, "9.9");
  EXPECT_EQ(s.identification.sensor_name, "LD-OEM1000");
}

TEST(SceneLoader, DeviceSection_IsTheD3SpellingOfScanner) {
  const Scene scene = load_ok("device: {identification: {sensor_name: LD-OEM1000-X}}");
  EXPECT_EQ(scene.scanner.identification.sensor_name, "LD-OEM1000-X");
}

TEST(SceneLoader, GivenCalibration_WinsAndDerivesMaxRange) {
  OpticsConfig optics;
  const double calibration = calibration_for_max_range(optics, 40.0);
  const Scene scene = load_ok("scanner: {optics: {calibration: " + std::to_string(calibration) + "}}");
  EXPECT_NEAR(scene.scanner.optics.max_range_at_full_reflectance_m, 40.0, 1e-4);
}

class MeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("ldoem-scene-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(folder_ / name) << text; }
  std::filesystem::path folder_;
};

TEST_F(MeshFiles, ObjWithScale_LoadsScaledTriangles) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  write("scene.yaml", "objects: [{mesh: {file: tri.obj, scale: [2, 3, 1]}}]\n");
  auto result = load_scene(folder_ / "scene.yaml");
  ASSERT_TRUE(result) << result.error().message();
  const auto& mesh = std::get<Mesh>(result->objects[0].shape);
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.vertices_m.size(), 4u);
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
  for (const auto& v : mesh.vertices_m) max = max.cwiseMax(v);
  EXPECT_EQ(max, Eigen::Vector3f(2, 3, 0));
  EXPECT_EQ(mesh.path, "tri.obj");
}

TEST_F(MeshFiles, AsciiStl_Loads) {
  write("q.stl", "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                 "endloop\nendfacet\nendsolid q\n");
  const std::string path = (folder_ / "inline.yaml").string();
  auto result = load_scene_from_string("objects: [{mesh: {file: q.stl}}]", path);
  ASSERT_TRUE(result) << result.error().message();
  EXPECT_EQ(std::get<Mesh>(result->objects[0].shape).triangles.size(), 1u);
}

TEST_F(MeshFiles, UnreadableMesh_IsMeshError) {
  write("junk.obj", "this is not a mesh\n");
  auto result = load_scene_from_string("objects: [{mesh: {file: junk.obj}}]", (folder_ / "s.yaml").string());
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::mesh);
  EXPECT_EQ(result.error().key_path, "objects[0].mesh.file");
}

TEST(SceneLoader, MissingSceneFile_IsIoError) {
  auto result = load_scene("/nonexistent/ldoem/scene.yaml");
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::io);
  EXPECT_EQ(result.error().message(), "/nonexistent/ldoem/scene.yaml: cannot open scene file: No such file or directory");
}

TEST(SceneLoader, EffectNames_RoundTrip) {
  for (std::size_t i = 0; i < kEffectCount; ++i) {
    const auto effect = static_cast<Effect>(i);
    // intensity too: incidence and atmosphere alone would change nothing and are refused.
    const std::string name(effect_name(effect));
    const Scene scene = load_ok(effect == Effect::intensity ? "effects: [intensity]" : "effects: [intensity, " + name + "]");
    EXPECT_TRUE(scene.effects.has(effect)) << effect_name(effect);
  }
}

}  // namespace
}  // namespace ldoem::scene
