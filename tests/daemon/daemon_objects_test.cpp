// The control socket's object commands on a daemon (D12 runtime changes): in-process on the
// memory endpoint with virtual time, the commands handed to the daemon's ControlTarget between
// loop rounds exactly as the socket hands them (control_socket::handle_line).
#include <gtest/gtest.h>

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
using protocol::SimTime;

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

  explicit ObjectDaemon(const std::string& scene_text) {
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
      {{{"name", 3}, {"position_m", {1, 2, 3}}}, "name must be"},
      {{{"name", "post"}}, "needs position_m"},
      {{{"name", "post"}, {"position_m", {1, 2}}}, "three numbers"},
      {{{"name", "post"}, {"position_m", "here"}}, "three numbers"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"rpy_deg", {0, "x", 0}}}, "rpy_deg"},
      {{{"name", "post"}, {"position_m", {1e300, 0, 0}}}, "beyond 1e4 m"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"at_s", -1}}, "at_s"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"at_s", now_s - 0.5}}, "in the past"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"keep_velocity", "yes"}}, "keep_velocity"},
      {{{"name", "post"}, {"position_m", {1, 2, 3}}, {"colour", "red"}}, "unknown argument 'colour'"},
      {{{"name", "ghost"}, {"position_m", {1, 2, 3}}}, "no moving object named 'ghost'"},
      {{{"name", "wall"}, {"position_m", {1, 2, 3}}}, "no moving object named 'wall'"},
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

TEST(DaemonObjects, MoveObjectInAStaticScene_SaysNothingMovesThere) {
  ObjectDaemon d(minimal_scene_text());
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

}  // namespace
}  // namespace ldoem::daemon::test
