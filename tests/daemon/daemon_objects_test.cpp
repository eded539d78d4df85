// The control socket's object commands on a daemon (D12 runtime changes): in-process on the
// memory endpoint with virtual time, the commands handed to the daemon's ControlTarget between
// loop rounds exactly as the socket hands them (control_socket::handle_line).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/daemon/daemon.hpp"
#include "ldoem/daemon/device_instance.hpp"
#include "ldoem/endpoints/memory_endpoint.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/text.hpp"
#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;
using endpoints::MemoryEndpoint;
using nlohmann::json;
using base::SimTime;

constexpr auto kWallLimit = 30s;

// The wall 5 m ahead (minimal scene) and a post hidden 15 m behind it, movable (zero velocity).
std::string post_scene_text() {
  return minimal_scene_text() +
         "  - name: post\n"
         "    box: {size_m: [0.4, 0.4, 6]}\n"
         "    pose: {position_m: [20, 0, 0]}\n"
         "    motion: {linear_velocity_mps: [0, 0, 0]}\n";
}

struct ObjectDaemon {
  TempDir dir;
  std::ostringstream out;
  std::ostringstream log;
  MemoryEndpoint* host = nullptr;
  std::unique_ptr<Daemon> daemon;
  std::string failure;
  std::string event_log = dir.path("events.log");

  // with_control: --control (an editable world: objects may be added, removed and moved).
  explicit ObjectDaemon(const std::string& scene_text, bool with_control = true) {
    auto scene = scene::load_scene_from_string(scene_text, "scene.yaml");
    if (!scene) {
      failure = scene.error().message();
      return;
    }
    Options options;
    options.can_interface.reset();
    options.flash_mode = FlashMode::memory;
    options.virtual_time = true;
    options.event_log_path = event_log;
    if (with_control) options.control_path = dir.path("ctl.sock");
    auto memory = std::make_unique<MemoryEndpoint>();
    host = memory.get();
    std::vector<std::unique_ptr<endpoints::HostEndpoint>> extra;
    extra.push_back(std::move(memory));
    auto created = Daemon::create(std::move(options), std::move(*scene), out, log, std::move(extra));
    if (!created) {
      failure = created.error().message;
      return;
    }
    daemon = std::move(*created);
  }
  json command(const json& request) {
    return json::parse(control_socket::handle_line(request.dump(), *daemon->control_target()));
  }
  std::vector<MemoryEndpoint::Sent> exchange(std::string_view text, std::size_t count = 1) {
    host->host_sends(1, telegram(text));
    daemon->run_until([&] { return host->sent_count() >= count; }, kWallLimit);
    return host->take_sent();
  }
  void start_measuring() {
    exchange("TRANS_ROTATE 0000");
    exchange("TRANS_MEASURE");
  }
  std::string events() const {
    std::ifstream file(event_log);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
  }
};

double seconds(SimTime t) { return std::chrono::duration<double>(t).count(); }

std::uint16_t ahead(const MemoryEndpoint::Sent& sent) {
  const auto profile = protocol::decode_profile(sent.payload);
  EXPECT_TRUE(profile);
  return profile ? distance_at_angle_zero(*profile).value_or(0) : 0;
}

json move_post(double x, double at_s) {
  return {{"execute", "move-object"},
          {"arguments", {{"name", "post"}, {"position_m", {x, 0, 0}}, {"at_s", at_s}}},
          {"id", "m"}};
}

// The post moved in front of the wall at T: profiles of revolutions that end before T see the
// wall (5 m = 1280), those that start after T see the post's face (2.8 m = 716.8).
TEST(DaemonObjects, MoveObject_SeenFromItsDeviceTimeOnAndNotBefore) {
  ObjectDaemon d(post_scene_text());
  ASSERT_TRUE(d.daemon) << d.failure;
  d.start_measuring();
  const double move_s = seconds(d.daemon->now()) + 0.55;
  const json reply = d.command(move_post(3.0, move_s));
  ASSERT_TRUE(reply.contains("return")) << reply.dump();
  EXPECT_EQ(reply["id"], "m");
  EXPECT_DOUBLE_EQ(reply["return"]["at_s"].get<double>(), move_s);
  const auto profiles = d.exchange("GET_PROFILE 0014 39ff", 20);
  ASSERT_EQ(profiles.size(), 20u);
  int before = 0;
  int after = 0;
  for (const auto& sent : profiles) {
    const double end_s = seconds(sent.at);
    if (end_s < move_s) {
      EXPECT_EQ(ahead(sent), 1280) << "at " << end_s;
      ++before;
    } else if (end_s - 0.1 > move_s) {
      EXPECT_NEAR(ahead(sent), 716.8, 1.0) << "at " << end_s;
      ++after;
    }
  }
  EXPECT_GE(before, 4);
  EXPECT_GE(after, 10);
  EXPECT_NE(d.events().find(R"("event":"OBJECT_MOVED")"), std::string::npos) << d.events();
  EXPECT_NE(d.events().find(R"("name":"post")"), std::string::npos) << d.events();
}

// Bad move-object requests get error objects; the daemon goes on answering.
TEST(DaemonObjects, MoveObjectGarbage_GetsErrorObjectsAndTheDaemonLives) {
  ObjectDaemon d(post_scene_text());
  ASSERT_TRUE(d.daemon) << d.failure;
  d.start_measuring();
  const double now_s = seconds(d.daemon->now());
  const std::vector<std::pair<json, std::string>> cases{
      {json::object(), "needs name"},
      {{{"name", 3}, {"position_m", {1, 2, 3}}}, "name: must be"},
      {{{"name", "post"}}, "needs position_m"},
      {{{"name", "post"}, {"position_m", {1, 2}}}, "three numbers"},
      {{{"name", "post"}, {"position_m", "here"}}, "three numbers"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"rpy_deg", {0, "x", 0}}}, "rpy_deg"},
      {{{"name", "post"}, {"position_m", {1e300, 0, 0}}}, "beyond 1e4 m"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"at_s", -1}}, "at_s"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"at_s", now_s - 0.5}}, "in the past"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"keep_velocity", "yes"}}, "keep_velocity"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"colour", "red"}}, "unknown argument 'colour'"},
      {{{"name", "ghost"}, {"position_m", {1, 2, 3}}}, "no object named 'ghost'"},
  };
  for (const auto& [arguments, expected] : cases) {
    const json reply = d.command({{"execute", "move-object"}, {"arguments", arguments}});
    ASSERT_TRUE(reply.contains("error")) << arguments.dump() << " -> " << reply.dump();
    EXPECT_EQ(reply["error"]["class"], "GenericError");
    EXPECT_NE(reply["error"]["desc"].get<std::string>().find(expected), std::string::npos)
        << arguments.dump() << " -> " << reply.dump();
  }
  const auto status = d.exchange("GET_STATUS");
  ASSERT_EQ(status.size(), 1u);
  EXPECT_EQ(protocol::format_telegram(status[0].payload), "GET_STATUS reply 0000 0003");
  EXPECT_EQ(d.events().find("OBJECT_MOVED"), std::string::npos) << "nothing was moved";
}

// Without --control a static scene builds no editable world (effects on demand): the commands
// cannot arrive then, and the target says so if handed one.
TEST(DaemonObjects, MoveObjectInAStaticSceneWithoutControl_IsRefused) {
  ObjectDaemon d(minimal_scene_text(), false);
  ASSERT_TRUE(d.daemon) << d.failure;
  const json reply = d.command({{"execute", "move-object"}, {"arguments", {{"name", "wall"}, {"position_m", {1, 2, 3}}}}});
  ASSERT_TRUE(reply.contains("error")) << reply.dump();
  EXPECT_NE(reply["error"]["desc"].get<std::string>().find("wall"), std::string::npos) << reply.dump();
}

// The same scene and the same commands at the same device times: the same bytes, twice.
TEST(DaemonObjects, SameCommandsAtTheSameDeviceTimes_GiveTheSameBytes) {
  auto run = [] {
    ObjectDaemon d(post_scene_text());
    EXPECT_TRUE(d.daemon) << d.failure;
    std::string bytes;
    if (!d.daemon) return bytes;
    int post_seen = 0;
    d.start_measuring();
    EXPECT_TRUE(d.command(move_post(3.0, 3.0)).contains("return"));
    EXPECT_TRUE(d.command(move_post(4.0, 3.42)).contains("return"));
    for (const auto& sent : d.exchange("GET_PROFILE 0010 39ff", 16)) {
      bytes += std::to_string(sent.at.count()) + " " + protocol::format_telegram(sent.payload) + "\n";
      if (ahead(sent) == 717) ++post_seen;
    }
    EXPECT_GT(post_seen, 0) << "the move was seen";
    return bytes;
  };
  const std::string first = run();
  EXPECT_EQ(first, run());
}

// Profiles of a fixed conversation: start, then `count` profiles, with `commands` handed over
// after the start (at device times given in them).
struct ScriptedConversation {
  std::vector<MemoryEndpoint::Sent> profiles;
  std::vector<json> replies;
  std::string events;
};

ScriptedConversation converse(const std::string& scene_text, bool with_control, const std::vector<json>& commands,
                      std::size_t count = 24) {
  ObjectDaemon d(scene_text, with_control);
  ScriptedConversation c;
  EXPECT_TRUE(d.daemon) << d.failure;
  if (!d.daemon) return c;
  d.start_measuring();
  for (const json& command : commands) c.replies.push_back(d.command(command));
  char request[32];
  std::snprintf(request, sizeof(request), "GET_PROFILE %04zx 39ff", count);
  c.profiles = d.exchange(request, count);
  c.events = d.events();
  return c;
}

json at(const char* command, json arguments) { return {{"execute", command}, {"arguments", std::move(arguments)}}; }

const json kCrate = json::parse(R"({"name": "crate", "box": {"size_m": [0.4, 0.4, 6]}, "pose": {"position_m": [3, 0, 0]},
                                    "reflectance": 0.5})");

// A static scene behind --control (world::SceneCaster, not EmbreeRayCaster alone) gives the
// same bytes as without it when no command is sent.
TEST(DaemonObjects, EditableStaticScene_WithoutCommands_SameBytes) {
  const auto plain = converse(minimal_scene_text(), false, {});
  const auto editable = converse(minimal_scene_text(), true, {});
  ASSERT_EQ(plain.profiles.size(), 24u);
  ASSERT_EQ(editable.profiles.size(), 24u);
  for (std::size_t i = 0; i < plain.profiles.size(); ++i) {
    EXPECT_EQ(plain.profiles[i].at, editable.profiles[i].at);
    EXPECT_EQ(plain.profiles[i].payload, editable.profiles[i].payload) << "profile " << i;
  }
}

// add-object then remove-object, static and moving: the object is there between the two device
// times only, and after the removal the profiles are the original bytes again.
TEST(DaemonObjects, AddThenRemove_GivesBackTheOriginalProfileBytes) {
  json walker = kCrate;
  walker["name"] = "walker";
  walker["motion"] = {{"linear_velocity_mps", {0, 0, 0}}};
  for (const json& object : {kCrate, walker}) {
    const auto original = converse(minimal_scene_text(), true, {});
    ASSERT_EQ(original.profiles.size(), 24u);
    const double added_s = seconds(original.profiles[4].at) + 0.01;
    const double removed_s = seconds(original.profiles[12].at) + 0.01;
    const std::string name = object["name"];
    const auto changed = converse(minimal_scene_text(), true,
                                  {at("add-object", {{"object", object}, {"at_s", added_s}}),
                                   at("remove-object", {{"name", name}, {"at_s", removed_s}})});
    ASSERT_EQ(changed.profiles.size(), 24u) << name;
    for (const json& reply : changed.replies) ASSERT_TRUE(reply.contains("return")) << reply.dump();
    int unchanged = 0;
    int with_object = 0;
    for (std::size_t i = 0; i < 24; ++i) {
      const double start_s = seconds(changed.profiles[i].at) - 0.1;
      const double end_s = seconds(changed.profiles[i].at);
      if (end_s < added_s || start_s > removed_s) {
        EXPECT_EQ(changed.profiles[i].payload, original.profiles[i].payload) << name << " profile " << i;
        ++unchanged;
      } else if (start_s > added_s && end_s < removed_s) {
        EXPECT_NEAR(ahead(changed.profiles[i]), 716.8, 1.0) << name << " profile " << i;  // 2.8 m: the crate's face
        ++with_object;
      }
    }
    EXPECT_GE(unchanged, 12) << name;  // 4 before, about 10 after
    EXPECT_GE(with_object, 6) << name;
    EXPECT_NE(changed.events.find(R"("event":"OBJECT_ADDED")"), std::string::npos) << changed.events;
    EXPECT_NE(changed.events.find(R"("event":"OBJECT_REMOVED")"), std::string::npos) << changed.events;
  }
}

// A static object of the scene moves too once the world is editable: the wall comes to 3 m.
TEST(DaemonObjects, MoveStaticObject_InAnEditableWorld) {
  ObjectDaemon d(minimal_scene_text());
  ASSERT_TRUE(d.daemon) << d.failure;
  d.start_measuring();
  const double move_s = seconds(d.daemon->now()) + 0.35;
  const json reply = d.command(at("move-object", {{"name", "wall"}, {"position_m", {3.1, 0, 0}}, {"at_s", move_s}}));
  ASSERT_TRUE(reply.contains("return")) << reply.dump();
  int before = 0;
  int after = 0;
  for (const auto& sent : d.exchange("GET_PROFILE 000a 39ff", 10)) {
    if (seconds(sent.at) < move_s) before += ahead(sent) == 1280;
    if (seconds(sent.at) - 0.1 > move_s) after += ahead(sent) == 768;  // 3 m
  }
  EXPECT_GE(before, 2);
  EXPECT_GE(after, 5);
}

// Bad add-object / remove-object requests get error objects that say why; the world is unchanged.
TEST(DaemonObjects, AddRemoveGarbage_GetsErrorObjects) {
  ObjectDaemon d(post_scene_text());
  ASSERT_TRUE(d.daemon) << d.failure;
  d.start_measuring();
  const double later_s = seconds(d.daemon->now()) + 5.0;
  ASSERT_TRUE(d.command(at("add-object", {{"object", kCrate}, {"at_s", later_s}})).contains("return"));
  json negative = kCrate;
  negative["name"] = "flat";
  negative["box"]["size_m"] = {1, -1, 1};
  json nameless = kCrate;
  nameless.erase("name");
  const std::vector<std::pair<json, std::string>> cases{
      {at("add-object", json::object()), "needs object"},
      {at("add-object", {{"object", "box"}}), "object: must be"},
      {at("add-object", {{"object", nameless}}), "needs a name"},
      {at("add-object", {{"object", kCrate}, {"at_s", later_s + 1}}), "exists already"},
      {at("add-object", {{"object", json::parse(R"({"name": "floor", "plane": {"normal": [0, 0, 1]}})")}}), "planes"},
      {at("add-object", {{"object", negative}}), "object.box.size_m"},
      {at("add-object", {{"object", {{"name", "x"}, {"cone", {{"radius_m", 1}}}}}}), "object"},
      {at("add-object", {{"object", {{"name", "m"}, {"mesh", {{"file", "/nonexistent.stl"}}}}}}), "object"},
      {at("add-object", {{"object", {{"name", "y"}, {"sphere", {{"radius_m", 1}}}}}, {"at_s", later_s - 1}}), "before a change"},
      // Static changes come in device-time order: one before the crate's time is refused.
      {at("remove-object", {{"name", "wall"}, {"at_s", later_s - 1}}), "before a change"},
      {at("move-object", {{"name", "wall"}, {"position_m", {3, 0, 0}}, {"at_s", later_s - 1}}), "before a change"},
      {at("remove-object", json::object()), "needs name"},
      {at("remove-object", {{"name", "ghost"}}), "no object named 'ghost'"},
      {at("remove-object", {{"name", "wall"}, {"at_s", 0.5}}), "in the past"},
      {at("remove-object", {{"name", "wall"}, {"when", 3}}), "unknown argument 'when'"},
  };
  for (const auto& [request, expected] : cases) {
    const json reply = d.command(request);
    ASSERT_TRUE(reply.contains("error")) << request.dump() << " -> " << reply.dump();
    EXPECT_EQ(reply["error"]["class"], "GenericError");
    EXPECT_NE(reply["error"]["desc"].get<std::string>().find(expected), std::string::npos)
        << request.dump() << " -> " << reply.dump();
  }
  const auto profile = d.exchange("GET_PROFILE 0001 39ff");
  ASSERT_EQ(profile.size(), 1u);
  EXPECT_EQ(ahead(profile[0]), 1280) << "nothing in front of the wall before the crate's time";
}

// A `dynamics` body added through the socket joins the running world at its step (the reply's
// at_s): a 2 m cube dropped 0.3 m onto a floor in front of the wall, its face 2 m ahead (512)
// from then on, falling or at rest; profiles before are the bytes without it; twice the same.
TEST(DaemonObjects, AddedBody_JoinsAtItsStepAndIsSeenFromThen) {
  const std::string scene = minimal_scene_text() + "  - plane: {normal: [0, 0, 1], offset_m: -1}\n";
  const auto original = converse(scene, true, {});
  ASSERT_EQ(original.profiles.size(), 24u);
  const double added_s = seconds(original.profiles[4].at) + 0.01;
  const json cube = json::parse(R"({"name": "cube", "box": {"size_m": [2, 2, 2]}, "pose": {"position_m": [3, 0, 0.3]},
                                    "dynamics": {"mass_kg": 20, "restitution": 0}})");
  const auto run = [&] { return converse(scene, true, {at("add-object", {{"object", cube}, {"at_s", added_s}})}); };
  const auto changed = run();
  ASSERT_EQ(changed.profiles.size(), 24u);
  ASSERT_TRUE(changed.replies[0].contains("return")) << changed.replies[0].dump();
  const double joined_s = changed.replies[0]["return"]["at_s"].get<double>();
  EXPECT_GE(joined_s, added_s);
  EXPECT_LT(joined_s, added_s + 0.002) << "steps up to added_s not yet computed: it joins at once";
  int before = 0;
  int with_cube = 0;
  for (std::size_t i = 0; i < 24; ++i) {
    const double end_s = seconds(changed.profiles[i].at);
    if (end_s < joined_s) {
      EXPECT_EQ(changed.profiles[i].payload, original.profiles[i].payload) << "profile " << i;
      ++before;
    } else if (end_s - 0.1 > joined_s) {
      EXPECT_EQ(ahead(changed.profiles[i]), 512) << "profile " << i;
      ++with_cube;
    }
  }
  EXPECT_GE(before, 4);
  EXPECT_GE(with_cube, 15);
  EXPECT_NE(changed.events.find(R"("event":"OBJECT_ADDED")"), std::string::npos) << changed.events;
  const auto again = run();
  ASSERT_EQ(again.profiles.size(), 24u);
  for (std::size_t i = 0; i < 24; ++i) EXPECT_EQ(again.profiles[i].payload, changed.profiles[i].payload) << i;
}

}  // namespace
}  // namespace ldoem::daemon::test
