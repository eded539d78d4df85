// ldoem-emud --replay with --control and --event-log (issue 22, docs/replay.md): the monitor
// serves a recorded device. query-status, query-faults and quit work, the host connections
// reach the event log, and the commands that need a control unit or a scene world answer a
// GenericError that says why. The capture is recorded first by ldoem-emud itself.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>

#include <nlohmann/json.hpp>

#include "control_client.hpp"
#include "daemon_process.hpp"
#include "host_link.hpp"

namespace ldoem::daemon::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

std::string replay_reply(TcpHost& host, std::string_view request) {
  host.send(telegram(request));
  const auto payload = host.next_payload(5s);
  return payload ? protocol::format_telegram(*payload) : std::string("(nothing)");
}

// One GET_STATUS against the minimal scene, recorded to `capture`; its reply.
std::string record_get_status(const TempDir& dir, const std::string& capture) {
  auto daemon = DaemonProcess::start({"--scene", dir.write("scene.yaml", minimal_scene_text()), "--no-can", "--tcp",
                                      "tcp:127.0.0.1:0", "--no-flash", "--virtual-time", "--record", capture});
  if (!daemon || !daemon->wait_ready()) return "(no daemon)";
  std::string reply = "(no host)";
  if (auto host = TcpHost::connect(daemon->tcp_port())) reply = replay_reply(*host, "GET_STATUS");
  daemon->signal(SIGTERM);
  daemon->wait();
  return reply;
}

struct ReplayWithControl {
  TempDir dir;
  std::string capture = dir.path("r.pcapng");
  std::string control_path = dir.path("ctl.sock");
  std::string event_log = dir.path("events.log");
  std::string recorded_reply = record_get_status(dir, capture);
  std::optional<DaemonProcess> daemon = DaemonProcess::start({"--replay", capture, "--tcp", "tcp:127.0.0.1:0",
                                                              "--virtual-time", "--control", control_path,
                                                              "--event-log", event_log});
  bool ready() { return daemon && daemon->wait_ready(); }
};

std::vector<json> event_log_lines(const std::string& path) {
  std::vector<json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line, nullptr, false));
  return lines;
}

TEST(DaemonReplayControl, StatusQuitAndConnectionEvents) {
  ReplayWithControl replay;
  ASSERT_NE(replay.recorded_reply.front(), '(') << replay.recorded_reply;
  ASSERT_TRUE(replay.ready()) << (replay.daemon ? replay.daemon->stderr_text() : "");
  auto control = ControlClient::connect(replay.control_path);
  ASSERT_TRUE(control);
  const auto greeting = control->next();
  ASSERT_TRUE(greeting && greeting->contains("QMP")) << (greeting ? greeting->dump() : "none");

  const auto status = control->execute({{"execute", "query-status"}, {"id", 1}});
  ASSERT_TRUE(status && status->contains("return")) << (status ? status->dump() : "none");
  const json& answer = (*status)["return"];
  EXPECT_EQ(answer["state"], "RECORDED");
  EXPECT_EQ(answer["powered"], true);
  EXPECT_EQ(answer["faults_active"], 0);
  EXPECT_FALSE(answer.contains("status_byte"));
  ASSERT_TRUE(answer.contains("counters"));

  {
    auto host = TcpHost::connect(replay.daemon->tcp_port());
    ASSERT_TRUE(host);
    EXPECT_EQ(replay_reply(*host, "GET_STATUS"), replay.recorded_reply);
  }  // closed here
  ASSERT_TRUE(control->wait_event("CONNECTION_CLOSED", 5s, "transport", "tcp"));
  const auto after = control->execute({{"execute", "query-status"}});
  ASSERT_TRUE(after && after->contains("return"));
  EXPECT_EQ((*after)["return"]["counters"]["telegrams_received"], 1);
  EXPECT_EQ((*after)["return"]["counters"]["tcp_connections"], 1);

  const auto faults = control->execute({{"execute", "query-faults"}});
  ASSERT_TRUE(faults && faults->contains("return"));
  EXPECT_EQ((*faults)["return"], json::array());
  const auto commands = control->execute({{"execute", "query-commands"}});
  ASSERT_TRUE(commands && commands->contains("return") && (*commands)["return"].is_array());

  const auto quit = control->execute({{"execute", "quit"}, {"id", 9}});
  ASSERT_TRUE(quit && quit->contains("return")) << (quit ? quit->dump() : "none");
  EXPECT_EQ(replay.daemon->wait(), 0) << replay.daemon->stderr_text();

  // The event log has the connection, without the peer's port (D11: the same run, the same log).
  const std::vector<json> lines = event_log_lines(replay.event_log);
  std::vector<std::string> names;
  for (const json& line : lines) {
    ASSERT_TRUE(line.is_object() && line.contains("event")) << line.dump();
    names.push_back(line["event"]);
    EXPECT_EQ(line["data"]["transport"], "tcp");
    EXPECT_FALSE(line["data"].contains("peer"));
  }
  EXPECT_EQ(names, (std::vector<std::string>{"CONNECTION_OPENED", "CONNECTION_CLOSED"}));
}

TEST(DaemonReplayControl, CommandsThatNeedAControlUnitOrAWorld_SayWhy) {
  ReplayWithControl replay;
  ASSERT_TRUE(replay.ready()) << (replay.daemon ? replay.daemon->stderr_text() : "");
  auto control = ControlClient::connect(replay.control_path);
  ASSERT_TRUE(control && control->next());
  const std::vector<std::pair<json, std::string>> cases{
      {{{"execute", "inject-fault"}, {"arguments", {{"kind", "drop_reply"}}}}, "inject-fault"},
      {{{"execute", "inject-fault"}, {"arguments", {{"kind", "motor_stall"}}}}, "inject-fault"},
      {{{"execute", "power-cycle"}}, "power-cycle"},
      {{{"execute", "clear-fault"}}, "clear-fault"},
      {{{"execute", "move-object"}, {"arguments", {{"name", "wall"}, {"position_m", {1, 2, 0}}}}}, "move-object"},
      {{{"execute", "remove-object"}, {"arguments", {{"name", "wall"}}}}, "remove-object"},
  };
  for (const auto& [request, command] : cases) {
    const auto reply = control->execute(request);
    ASSERT_TRUE(reply && reply->contains("error")) << request.dump() << " -> " << (reply ? reply->dump() : "none");
    EXPECT_EQ((*reply)["error"]["class"], "GenericError") << request.dump();
    EXPECT_EQ((*reply)["error"]["desc"], command + ": not available for a recorded device (--replay)") << request.dump();
  }
  // The daemon still serves after them.
  const auto status = control->execute({{"execute", "query-status"}});
  ASSERT_TRUE(status && status->contains("return"));
  EXPECT_EQ((*status)["return"]["faults_active"], 0);
}

}  // namespace
}  // namespace ldoem::daemon::test
