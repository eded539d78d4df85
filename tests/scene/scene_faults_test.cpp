// The scene's `faults:` list (D11): good entries load, bad ones give located errors.
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

namespace ldoem::scene {
namespace {

using namespace std::chrono_literals;

TEST(SceneFaults, NoFaultsKeyMeansNoFaults) {
  auto scene = load_scene_from_string("seed: 3", "inline.yaml");
  ASSERT_TRUE(scene) << scene.error().message();
  EXPECT_TRUE(scene->faults.empty());
}

TEST(SceneFaults, EntriesLoadInOrder) {
  auto scene = load_scene_from_string(R"(
faults:
  - {kind: motor_stall, at_s: 2, duration_s: 1.5}
  - kind: drop_reply
    on: {service: GET_STATUS, nth: 3}
    transport: tcp
  - {kind: isotp_drop_cf, probability: 0.1}
  - {kind: blind, from_deg: 350, to_deg: 10}
  - {kind: window_dirt, fraction: 0.5}
)", "inline.yaml");
  ASSERT_TRUE(scene) << scene.error().message();
  ASSERT_EQ(scene->faults.size(), 5u);
  EXPECT_EQ(scene->faults[0].kind, faults::FaultKind::motor_stall);
  EXPECT_EQ(std::get<faults::TriggerAt>(scene->faults[0].trigger).at, faults::SimTime(2s));
  EXPECT_EQ(scene->faults[0].duration, faults::SimTime(1500ms));
  EXPECT_EQ(std::get<faults::TriggerOnNth>(scene->faults[1].trigger), (faults::TriggerOnNth{0x0102, 3}));
  EXPECT_EQ(scene->faults[1].transport, protocol::Transport::tcp);
  EXPECT_EQ(std::get<faults::TriggerProbability>(scene->faults[2].trigger).probability, 0.1);
  EXPECT_EQ(scene->faults[3].from_ticks, 5600);
  EXPECT_EQ(scene->faults[4].fraction, 0.5);
}

struct BadFault {
  const char* title;
  const char* yaml;
  SceneErrorKind kind;
  const char* key_path;
  int line;
  int column;
};

const BadFault kBadFaults[] = {
    {"unknown kind", "faults:\n  - {kind: motor_fire}", SceneErrorKind::unknown_fault, "faults[0].kind", 2, 12},
    {"negative time", "faults:\n  - {kind: motor_stall, at_s: -1}", SceneErrorKind::out_of_range, "faults[0].at_s", 2, 31},
    {"fraction over 1", "faults:\n  - {kind: window_dirt, fraction: 1.2}", SceneErrorKind::out_of_range,
     "faults[0].fraction", 2, 35},
    {"unknown service", "faults:\n  - kind: drop_reply\n    on: {service: GET_COFFEE, nth: 1}",
     SceneErrorKind::unknown_service, "faults[0].on.service", 3, 19},
    {"missing kind", "faults:\n  - {at_s: 1}", SceneErrorKind::missing_key, "faults[0].kind", 2, 5},
    {"two triggers", "faults:\n  - {kind: drop_reply, at_s: 1, probability: 0.5}", SceneErrorKind::conflicting_keys,
     "faults[0]", 2, 5},
    {"transport the kind has not", "faults:\n  - {kind: tcp_reset, transport: serial}",
     SceneErrorKind::conflicting_keys, "faults[0].transport", 2, 34},
    {"faults not a list", "faults: {kind: motor_stall}", SceneErrorKind::wrong_type, "faults", 1, 9},
    {"duplicate key", "faults:\n  - {kind: motor_stall, kind: blind}", SceneErrorKind::duplicate_key,
     "faults[0].kind", 2, 25},
    {"map for a number", "faults:\n  - {kind: motor_stall, at_s: {a: 1}}", SceneErrorKind::wrong_type,
     "faults[0].at_s", 2, 31},
};

class SceneFaultErrors : public ::testing::TestWithParam<BadFault> {};

TEST_P(SceneFaultErrors, LocatedError) {
  const BadFault& bad = GetParam();
  auto scene = load_scene_from_string(bad.yaml, "faulty.yaml");
  ASSERT_FALSE(scene) << bad.title;
  const SceneError& error = scene.error();
  EXPECT_EQ(error.kind, bad.kind) << error.message();
  EXPECT_EQ(error.key_path, bad.key_path) << error.message();
  EXPECT_EQ(error.line, bad.line) << error.message();
  EXPECT_EQ(error.column, bad.column) << error.message();
  EXPECT_EQ(error.message().rfind("faulty.yaml:" + std::to_string(bad.line) + ":", 0), 0u) << error.message();
}

INSTANTIATE_TEST_SUITE_P(Bad, SceneFaultErrors, ::testing::ValuesIn(kBadFaults));

}  // namespace
}  // namespace ldoem::scene
