// Issue 15: the `scanners:` list. One entry reads like `scanner:`; duplicates and bad entries
// are located errors; housings and per-scanner views.
#include "ldoem/scene/scanners.hpp"
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

#include <string>

namespace ldoem::scene {
namespace {

Scene load(const std::string& yaml) {
  auto scene = load_scene_from_string(yaml, "test.yaml");
  EXPECT_TRUE(scene.has_value()) << (scene ? "" : scene.error().message());
  return scene ? *scene : Scene{};
}

SceneError load_error(const std::string& yaml) {
  auto scene = load_scene_from_string(yaml, "test.yaml");
  EXPECT_FALSE(scene.has_value());
  return scene ? SceneError{} : scene.error();
}

const char* const kTwoScanners = R"(
seed: 7
effects: [noise, intensity, incidence]
scanners:
  - name: left
    pivot_pose: {position_m: [0, 0, 0.5]}
    endpoints: {tcp: "tcp:127.0.0.1:40001", can: "can:vcan0:6C0:6C1", serial: "serial:pty:/tmp/l.tty", lpt: "lpt:pty:/tmp/l.lpt"}
    flash_file: left.flash
  - name: right
    pivot_pose: {position_m: [2, 1, 0.5], rpy_deg: [0, 0, 90]}
    optical_offset_m: [0.01, 0, 0.02]
    effects: [noise]
    housing: {radius_m: 0.05, height_m: 0.2, reflectance: 0.5}
    endpoints: {tcp: "tcp:127.0.0.1:40002", lpt: "lpt:gpio:gpiochip0"}
objects:
  - {name: floor, plane: {normal: [0, 0, 1]}}
)";

TEST(Scanners, TwoEntriesCarryTheirOwnPoseEffectsAndEndpoints) {
  const Scene scene = load(kTwoScanners);
  ASSERT_EQ(scene.scanners.size(), 2u);
  EXPECT_EQ(scene.scanner_count(), 2u);
  const ScannerEntry& left = scene.scanners[0];
  const ScannerEntry& right = scene.scanners[1];
  EXPECT_EQ(left.name, "left");
  EXPECT_TRUE(left.effects.has(Effect::intensity));  // inherited
  EXPECT_TRUE(right.effects.has(Effect::noise));
  EXPECT_FALSE(right.effects.has(Effect::intensity));  // its own list replaces the scene's
  EXPECT_DOUBLE_EQ(right.config.pivot_pose.position_m.x(), 2.0);
  EXPECT_DOUBLE_EQ(right.config.optical_offset_m.z(), 0.02);
  EXPECT_DOUBLE_EQ(right.config.housing.radius_m, 0.05);
  ASSERT_TRUE(left.endpoints.tcp && right.endpoints.tcp);
  EXPECT_EQ(left.endpoints.tcp->address, "127.0.0.1");
  EXPECT_EQ(left.endpoints.tcp->port, 40001);
  EXPECT_EQ(right.endpoints.tcp->port, 40002);
  EXPECT_EQ(right.endpoints.tcp->address, "127.0.0.1");
  EXPECT_EQ(*left.endpoints.serial_pty, "/tmp/l.tty");
  EXPECT_FALSE(left.endpoints.lpt->gpio);
  EXPECT_TRUE(right.endpoints.lpt->gpio);
  EXPECT_EQ(right.endpoints.lpt->target, "gpiochip0");
  EXPECT_EQ(*left.flash_file, "left.flash");
  EXPECT_FALSE(right.flash_file.has_value());
  // The second scanner's flash answers on the next identifier pair of the plan (D1 + 2k).
  EXPECT_EQ(right.config.flash.can_request_id, 0x6C2);
  EXPECT_EQ(right.config.flash.can_response_id, 0x6C3);
  // `scanner` and `effects` are the first entry's, for the code that reads one scanner.
  EXPECT_DOUBLE_EQ(scene.scanner.pivot_pose.position_m.z(), 0.5);
  EXPECT_TRUE(scene.effects.has(Effect::incidence));
}

TEST(Scanners, OneEntryReadsLikeTheScannerSection) {
  const Scene single = load("seed: 3\neffects: [noise]\nscanner: {pivot_pose: {position_m: [1, 2, 3]}, max_range_m: 20}\n");
  const Scene listed = load("seed: 3\neffects: [noise]\nscanners:\n  - {name: only, pivot_pose: {position_m: [1, 2, 3]}, max_range_m: 20}\n");
  EXPECT_TRUE(single.scanners.empty());
  ASSERT_EQ(listed.scanners.size(), 1u);
  EXPECT_EQ(listed.scanner.pivot_pose.position_m, single.scanner.pivot_pose.position_m);
  EXPECT_EQ(listed.scanner.max_range_m, single.scanner.max_range_m);
  EXPECT_EQ(listed.scanner.flash.can_request_id, 0x6C0);
  const Scene view = scanner_view(listed, 0);
  EXPECT_EQ(view.seed, 3u);
  EXPECT_TRUE(view.effects.has(Effect::noise));
  EXPECT_TRUE(view.objects.empty());
}

TEST(Scanners, ViewsGiveEachScannerItsConfigurationAndSeed) {
  const Scene scene = load(kTwoScanners);
  const Scene right = scanner_view(scene, 1);
  EXPECT_EQ(right.seed, 8u);
  EXPECT_DOUBLE_EQ(right.scanner.pivot_pose.position_m.y(), 1.0);
  EXPECT_FALSE(right.effects.has(Effect::intensity));
  EXPECT_EQ(scanner_name(scene, 1), "right");
  EXPECT_EQ(scanner_name(load("scanner: {}"), 0), "scanner");
}

TEST(Scanners, HousingsOnlyWithTwoScannersOrMore) {
  Scene one = load("scanners: [{name: a}]\nobjects: [{plane: {normal: [0, 0, 1]}}]");
  EXPECT_TRUE(add_housings(one).empty());
  EXPECT_EQ(one.objects.size(), 1u);
  Scene single = load("scanner: {}");
  EXPECT_TRUE(add_housings(single).empty());
  EXPECT_TRUE(single.objects.empty());

  Scene two = load(kTwoScanners);
  const auto housings = add_housings(two);
  ASSERT_EQ(housings.size(), 2u);
  EXPECT_EQ(housings[0], 1u);
  EXPECT_EQ(housings[1], 2u);
  const SceneObject& right = two.objects[2];
  const auto& cylinder = std::get<Cylinder>(right.shape);
  EXPECT_DOUBLE_EQ(cylinder.radius_m, 0.05);
  EXPECT_DOUBLE_EQ(cylinder.length_m, 0.2);
  EXPECT_DOUBLE_EQ(right.reflectance, 0.5);
  EXPECT_DOUBLE_EQ(right.pose.position_m.x(), 2.0);
  const auto& left = std::get<Cylinder>(two.objects[1].shape);
  EXPECT_DOUBLE_EQ(left.radius_m, HousingConfig{}.radius_m);
}

struct BadEntry {
  const char* title;
  const char* yaml;
  SceneErrorKind kind;
  const char* key_path;
  int line;
};

const BadEntry kBadEntries[] = {
    {"both scanner and scanners", "scanner: {}\nscanners: [{name: a}]", SceneErrorKind::conflicting_keys, "scanners", 2},
    {"empty list", "scanners: []", SceneErrorKind::out_of_range, "scanners", 1},
    {"not a list", "scanners: {name: a}", SceneErrorKind::wrong_type, "scanners", 1},
    {"no name", "scanners:\n  - {max_range_m: 20}", SceneErrorKind::missing_key, "scanners[0].name", 2},
    {"bad name", "scanners:\n  - {name: \"a b\"}", SceneErrorKind::out_of_range, "scanners[0].name", 2},
    {"same name twice", "scanners:\n  - {name: a}\n  - {name: a}", SceneErrorKind::duplicate_key, "scanners[1].name", 3},
    {"unknown entry key", "scanners:\n  - {name: a, colour: red}", SceneErrorKind::unknown_key, "scanners[0].colour", 2},
    {"unknown endpoint", "scanners:\n  - {name: a, endpoints: {udp: 1}}", SceneErrorKind::unknown_key,
     "scanners[0].endpoints.udp", 2},
    {"same TCP port", "scanners:\n  - {name: a, endpoints: {tcp: \"tcp:127.0.0.1:40001\"}}\n  - {name: b, endpoints: {tcp: \"tcp:127.0.0.1:40001\"}}",
     SceneErrorKind::conflicting_keys, "scanners[1].endpoints.tcp", 3},
    {"bad TCP port", "scanners:\n  - {name: a, endpoints: {tcp: \"tcp:h:70000\"}}", SceneErrorKind::out_of_range,
     "scanners[0].endpoints.tcp", 2},
    {"same CAN ids", "scanners:\n  - {name: a}\n  - {name: b, endpoints: {can: \"can:vcan0:6C1:6C5\"}}",
     SceneErrorKind::conflicting_keys, "scanners[1].endpoints.can", 3},
    {"same CAN ids from flash", "scanners:\n  - {name: a}\n  - {name: b, flash: {can_request_id: 0x6C0, can_response_id: 0x6C7}}",
     SceneErrorKind::conflicting_keys, "scanners[1].flash.can_request_id", 3},
    {"CAN id beyond 11 bits", "scanners:\n  - {name: a, endpoints: {can: \"can:vcan0:800:6C1\"}}", SceneErrorKind::out_of_range,
     "scanners[0].endpoints.can", 2},
    {"CAN without ids", "scanners:\n  - {name: a, endpoints: {can: \"can:vcan0\"}}", SceneErrorKind::wrong_type,
     "scanners[0].endpoints.can", 2},
    // Issue 24: the keys and spellings from before docs/endpoints.md name the new ones.
    {"old can_ids key", "scanners:\n  - {name: a, endpoints: {can_ids: \"6C2:6C3\"}}", SceneErrorKind::unknown_key,
     "scanners[0].endpoints.can_ids", 2},
    {"old TCP spelling", "scanners:\n  - {name: a, endpoints: {tcp: \"127.0.0.1:40001\"}}", SceneErrorKind::wrong_type,
     "scanners[0].endpoints.tcp", 2},
    {"old bare port", "scanners:\n  - {name: a, endpoints: {tcp: 40001}}", SceneErrorKind::wrong_type,
     "scanners[0].endpoints.tcp", 2},
    {"old LPT spelling", "scanners:\n  - {name: a, endpoints: {lpt: \"pty:/tmp/x\"}}", SceneErrorKind::wrong_type,
     "scanners[0].endpoints.lpt", 2},
    {"same serial pty", "scanners:\n  - {name: a, endpoints: {serial: \"serial:pty:/tmp/s\"}}\n  - {name: b, endpoints: {lpt: \"lpt:pty:/tmp/s\"}}",
     SceneErrorKind::conflicting_keys, "scanners[1].endpoints.lpt", 3},
    {"serial on gpio", "scanners:\n  - {name: a, endpoints: {serial: \"lpt:gpio:chip\"}}", SceneErrorKind::wrong_type,
     "scanners[0].endpoints.serial", 2},
    {"same flash file", "scanners:\n  - {name: a, flash_file: f}\n  - {name: b, flash_file: f}", SceneErrorKind::conflicting_keys,
     "scanners[1].flash_file", 3},
    {"bad entry effect", "scanners:\n  - {name: a, effects: [noise, fog]}", SceneErrorKind::unknown_effect,
     "scanners[0].effects[1]", 2},
    {"bad entry effect combination", "scanners:\n  - {name: a, effects: [incidence]}", SceneErrorKind::conflicting_keys,
     "scanners[0].effects[0]", 2},
    {"bad housing", "scanners:\n  - {name: a, housing: {radius_m: 0}}", SceneErrorKind::out_of_range,
     "scanners[0].housing.radius_m", 2},
    {"bad scanner field", "scanners:\n  - {name: a}\n  - {name: b, max_range_m: 300}", SceneErrorKind::out_of_range,
     "scanners[1].max_range_m", 3},
    {"fog without waveform", "scanners:\n  - {name: a, atmosphere: {fog_returns: true}}", SceneErrorKind::conflicting_keys,
     "scanners[0].atmosphere.fog_returns", 2},
};

TEST(Scanners, BadEntriesAreLocatedErrors) {
  for (const BadEntry& bad : kBadEntries) {
    SCOPED_TRACE(bad.title);
    const SceneError error = load_error(bad.yaml);
    EXPECT_EQ(error.kind, bad.kind) << error.message();
    EXPECT_EQ(error.key_path, bad.key_path) << error.message();
    EXPECT_EQ(error.line, bad.line) << error.message();
    EXPECT_NE(error.message().find("test.yaml:"), std::string::npos);
  }
}

TEST(Scanners, ADuplicateNamesTheScannerThatHasItFirst) {
  const SceneError error =
      load_error("scanners:\n  - {name: front, endpoints: {tcp: \"tcp:127.0.0.1:40001\"}}\n  - {name: back, endpoints: {tcp: \"tcp:127.0.0.1:40001\"}}");
  EXPECT_NE(error.message().find("'front'"), std::string::npos) << error.message();
}

TEST(Scanners, AnOldSpellingNamesTheNewOne) {
  const SceneError old_key = load_error("scanners:\n  - {name: a, endpoints: {can_ids: \"6C2:6C3\"}}");
  EXPECT_NE(old_key.message().find("can_ids is the old key; write can: can:IF:6C2:6C3"), std::string::npos)
      << old_key.message();
  const SceneError old_tcp = load_error("scanners:\n  - {name: a, endpoints: {tcp: 40001}}");
  EXPECT_NE(old_tcp.message().find("`40001` is the old spelling; write tcp:127.0.0.1:40001 (docs/endpoints.md)"),
            std::string::npos)
      << old_tcp.message();
}

TEST(Scanners, EphemeralPortsMayRepeat) {
  const Scene scene = load("scanners:\n  - {name: a, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n  - {name: b, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}");
  EXPECT_EQ(scene.scanners.size(), 2u);
}

}  // namespace
}  // namespace ldoem::scene
