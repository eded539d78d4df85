// ldoem-emud with faults (D11): the control socket over a real daemon, scene-scripted wire
// faults on TCP, and the determinism of bytes and event log. Host-only (TCP and a UNIX socket).
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "control_client.hpp"
#include "daemon_process.hpp"
#include "host_link.hpp"

namespace ldoem::daemon::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

struct FaultDaemon {
  TempDir dir;
  std::string control_path = dir.path("ctl.sock");
  std::string event_log = dir.path("events.log");
  std::optional<DaemonProcess> daemon;

  explicit FaultDaemon(const std::string& scene_text) : daemon(DaemonProcess::start(arguments(scene_text))) {}
  std::vector<std::string> arguments(const std::string& scene_text) const {
    return {"--scene", dir.write("scene.yaml", scene_text), "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
            "--virtual-time", "--control", control_path, "--event-log", event_log};
  }
  bool ready() { return daemon && daemon->wait_ready(); }
};

std::string reply_text(TcpHost& host, std::string_view request, std::chrono::milliseconds limit = 5s) {
  host.send(telegram(request));
  const auto payload = host.next_payload(limit);
  return payload ? protocol::format_telegram(*payload) : std::string("(nothing)");
}

TEST(DaemonFaults, ControlSocketIsOffByDefault) {
  TempDir dir;
  auto daemon = DaemonProcess::start({"--scene", dir.write("scene.yaml", minimal_scene_text()), "--no-can", "--tcp",
                                      "tcp:127.0.0.1:0", "--no-flash", "--virtual-time"});
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  for (const auto& entry : std::filesystem::directory_iterator(dir.path(""))) {
    EXPECT_NE(entry.path().extension(), ".sock") << entry.path();
  }
  EXPECT_EQ(daemon->endpoints().count("control"), 0u);
}

TEST(DaemonFaults, EncoderErrorThroughTheControlSocket_StatusB4OverTcp) {
  FaultDaemon fd(minimal_scene_text());
  ASSERT_TRUE(fd.ready()) << fd.daemon->stderr_text();
  struct stat info {};
  ASSERT_EQ(stat(fd.control_path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0600u);
  auto control = ControlClient::connect(fd.control_path);
  ASSERT_TRUE(control);
  const auto greeting = control->next();
  ASSERT_TRUE(greeting && greeting->contains("QMP")) << (greeting ? greeting->dump() : "none");
  auto host = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(reply_text(*host, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  EXPECT_EQ(reply_text(*host, "TRANS_MEASURE"), "TRANS_MEASURE reply 0000 0003 0000");
  const auto injected = control->execute({{"execute", "inject-fault"}, {"arguments", {{"kind", "encoder_error"}}}, {"id", 1}});
  ASSERT_TRUE(injected);
  EXPECT_EQ((*injected)["id"], 1);
  ASSERT_TRUE(injected->contains("return")) << injected->dump();
  EXPECT_EQ(reply_text(*host, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
  EXPECT_EQ(reply_text(*host, "TRANS_IDLE"), "SERVICE_FAILURE 0402 0003");
  const auto event = control->wait_event("STATE_CHANGED", 5s, "to", "ERROR");
  ASSERT_TRUE(event);
  EXPECT_EQ((*event)["data"]["from"], "MEASURE");
  EXPECT_EQ((*event)["data"]["status_byte"], 0xB4);
  ASSERT_TRUE(control->wait_event("FAULT_INJECTED", 5s, "kind", "encoder_error"));
  const auto status = control->execute({{"execute", "query-status"}});
  ASSERT_TRUE(status);
  EXPECT_EQ((*status)["return"]["state"], "ERROR");
  EXPECT_EQ((*status)["return"]["status_byte"], 0xB4);
  // Cleared and reset: the head spins again.
  ASSERT_TRUE(control->execute({{"execute", "clear-fault"}}));
  EXPECT_EQ(reply_text(*host, "DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(reply_text(*host, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  const auto quit = control->execute({{"execute", "quit"}});
  ASSERT_TRUE(quit);
  EXPECT_EQ(fd.daemon->wait(), 0);
}

// Issue 15: with several scanners a fault command's "scanner" argument picks the device; the
// others carry on, and every event names its scanner.
TEST(DaemonFaults, TwoScanners_TheScannerArgumentPutsTheFaultOnThatScannerOnly) {
  TempDir dir;
  const std::string control_path = dir.path("ctl.sock");
  const std::string scene = dir.write("two.yaml", minimal_scene_text() +
                                                      "scanners:\n  - {name: a, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"
                                                      "  - {name: b, pivot_pose: {position_m: [0, 1, 0]}, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n");
  auto daemon = DaemonProcess::start(
      {"--scene", scene, "--no-can", "--no-flash", "--virtual-time", "--control", control_path});
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  auto control = ControlClient::connect(control_path);
  ASSERT_TRUE(control && control->next());
  auto host = TcpHost::connect(daemon->tcp_port());  // the last "tcp" line printed: scanner b's
  ASSERT_TRUE(host);
  EXPECT_EQ(reply_text(*host, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  EXPECT_EQ(reply_text(*host, "TRANS_MEASURE"), "TRANS_MEASURE reply 0000 0003 0000");
  const auto injected = control->execute(
      {{"execute", "inject-fault"}, {"arguments", {{"kind", "encoder_error"}, {"scanner", "b"}}}});
  ASSERT_TRUE(injected && injected->contains("return")) << (injected ? injected->dump() : "none");
  EXPECT_EQ(reply_text(*host, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
  const auto event = control->wait_event("FAULT_INJECTED", 5s, "kind", "encoder_error");
  ASSERT_TRUE(event);
  EXPECT_EQ((*event)["data"]["scanner"], "b");
  const auto changed = control->wait_event("STATE_CHANGED", 5s, "to", "ERROR");
  ASSERT_TRUE(changed);
  EXPECT_EQ((*changed)["data"]["scanner"], "b");
  const auto b = control->execute({{"execute", "query-status"}, {"arguments", {{"scanner", "b"}}}});
  ASSERT_TRUE(b);
  EXPECT_EQ((*b)["return"]["state"], "ERROR");
  EXPECT_EQ((*b)["return"]["faults_active"], 1);
  const auto a = control->execute({{"execute", "query-status"}});  // no argument: the first scanner
  ASSERT_TRUE(a);
  EXPECT_EQ((*a)["return"]["state"], "IDLE");
  EXPECT_EQ((*a)["return"]["faults_active"], 0);
  const auto unknown = control->execute({{"execute", "query-faults"}, {"arguments", {{"scanner", "c"}}}});
  ASSERT_TRUE(unknown);
  EXPECT_EQ((*unknown)["error"]["desc"], "scanner: no scanner named 'c'");
  ASSERT_TRUE(control->execute({{"execute", "quit"}}));
  EXPECT_EQ(daemon->wait(), 0);
}

TEST(DaemonFaults, SceneDropsTheSecondGetStatusReplyOnTcp) {
  FaultDaemon fd(minimal_scene_text() + "faults:\n  - kind: drop_reply\n    on: {service: GET_STATUS, nth: 2}\n");
  ASSERT_TRUE(fd.ready()) << fd.daemon->stderr_text();
  auto host = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(reply_text(*host, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  EXPECT_EQ(reply_text(*host, "GET_STATUS", 500ms), "(nothing)");
  EXPECT_EQ(reply_text(*host, "GET_STATUS"), "GET_STATUS reply 0000 0001");
}

TEST(DaemonFaults, TcpResetClosesTheConnectionAndTheNextOneWorks) {
  FaultDaemon fd(minimal_scene_text() + "faults:\n  - kind: tcp_reset\n    on: {service: GET_SIGNAL, nth: 1}\n");
  ASSERT_TRUE(fd.ready()) << fd.daemon->stderr_text();
  auto host = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(host);
  host->send(telegram("GET_SIGNAL"));
  EXPECT_TRUE(host->closed_by_peer(5s));
  auto again = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(again);
  EXPECT_EQ(reply_text(*again, "GET_SIGNAL"), "GET_SIGNAL reply 0000");
}

TEST(DaemonFaults, PowerCycleResetsTcpAndComesBackInPowerUpState) {
  FaultDaemon fd(minimal_scene_text());
  ASSERT_TRUE(fd.ready()) << fd.daemon->stderr_text();
  auto control = ControlClient::connect(fd.control_path);
  ASSERT_TRUE(control && control->next());
  auto host = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(reply_text(*host, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  ASSERT_TRUE(control->execute({{"execute", "power-cycle"}, {"arguments", {{"off_s", 0.5}}}}));
  EXPECT_TRUE(host->closed_by_peer(5s));
  ASSERT_TRUE(control->wait_event("BOOTED", 10s));  // connections are refused until the boot ends
  auto again = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(again);
  EXPECT_EQ(reply_text(*again, "GET_STATUS"), "GET_STATUS reply 0000 0001");
}

// Same scene, seed and conversation: the same bytes and the same event log, twice (D11).
TEST(DaemonFaults, SameSeedAndConversationGiveTheSameBytesAndEvents) {
  const std::string scene = minimal_scene_text() + "seed: 99\nfaults:\n"
                            "  - {kind: drop_reply, probability: 0.3, service: GET_STATUS}\n"
                            "  - {kind: truncate_reply, bytes_kept: 3, every: {service: GET_CONFIG, count: 2}}\n"
                            "  - kind: encoder_error\n    on: {service: TRANS_MEASURE, nth: 1}\n";
  auto run = [&scene]() {
    FaultDaemon fd(scene);
    EXPECT_TRUE(fd.ready()) << fd.daemon->stderr_text();
    std::string transcript;
    auto host = TcpHost::connect(fd.daemon->tcp_port());
    if (!host) return std::pair<std::string, std::string>{};
    auto ask = [&](std::string_view request) { transcript += std::string(request) + " -> " + reply_text(*host, request, 400ms) + "\n"; };
    for (int i = 0; i < 12; ++i) ask("GET_STATUS");
    for (int i = 0; i < 4; ++i) ask("GET_CONFIG 0010");
    ask("TRANS_ROTATE 0000");
    ask("TRANS_MEASURE");
    for (int i = 0; i < 6; ++i) ask("GET_STATUS");
    fd.daemon->signal(SIGTERM);
    fd.daemon->wait();
    std::ifstream log(fd.event_log);
    std::stringstream events;
    events << log.rdbuf();
    return std::pair{transcript, events.str()};
  };
  const auto first = run();
  const auto second = run();
  EXPECT_EQ(first.first, second.first);
  EXPECT_EQ(first.second, second.second);
  EXPECT_NE(first.first.find("(nothing)"), std::string::npos) << first.first;      // some drops happened
  EXPECT_NE(first.first.find("00b4"), std::string::npos) << first.first;           // the encoder fault
  EXPECT_NE(first.second.find("FAULT_INJECTED"), std::string::npos) << first.second;
}

// Issue 10 item 2: connections opened and closed are events, with the transport and the peer.
// The event log leaves the peer out (its port differs from run to run).
TEST(DaemonFaults, TcpConnectionsOpenedAndClosedAreEvents) {
  FaultDaemon fd(minimal_scene_text());
  ASSERT_TRUE(fd.ready()) << fd.daemon->stderr_text();
  auto control = ControlClient::connect(fd.control_path);
  ASSERT_TRUE(control && control->next());
  {
    auto host = TcpHost::connect(fd.daemon->tcp_port());
    ASSERT_TRUE(host);
    const auto opened = control->wait_event("CONNECTION_OPENED", 5s);
    ASSERT_TRUE(opened);
    EXPECT_EQ((*opened)["data"]["transport"], "tcp");
    EXPECT_EQ((*opened)["data"]["peer"].get<std::string>().rfind("127.0.0.1:", 0), 0u) << opened->dump();
    EXPECT_EQ(reply_text(*host, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  }
  const auto closed = control->wait_event("CONNECTION_CLOSED", 5s);
  ASSERT_TRUE(closed);
  EXPECT_EQ((*closed)["data"]["transport"], "tcp");
  EXPECT_TRUE((*closed)["data"].contains("peer"));
  ASSERT_TRUE(control->execute({{"execute", "quit"}}));
  EXPECT_EQ(fd.daemon->wait(), 0);
  std::ifstream log(fd.event_log);
  std::stringstream events;
  events << log.rdbuf();
  EXPECT_NE(events.str().find(R"("event":"CONNECTION_OPENED")"), std::string::npos) << events.str();
  EXPECT_NE(events.str().find(R"("event":"CONNECTION_CLOSED")"), std::string::npos) << events.str();
  EXPECT_EQ(events.str().find("peer"), std::string::npos) << events.str();
}

// The object commands over the real socket: a move is answered, garbage gets error objects.
TEST(DaemonFaults, ObjectCommandsOverTheSocket) {
  FaultDaemon fd(minimal_scene_text() +
                 "  - name: post\n    box: {size_m: [0.4, 0.4, 6]}\n    pose: {position_m: [20, 0, 0]}\n"
                 "    motion: {linear_velocity_mps: [0, 0, 0]}\n");
  ASSERT_TRUE(fd.ready()) << fd.daemon->stderr_text();
  auto control = ControlClient::connect(fd.control_path);
  ASSERT_TRUE(control && control->next());
  const auto moved = control->execute(
      {{"execute", "move-object"}, {"arguments", {{"name", "post"}, {"position_m", {3, 0, 0}}, {"at_s", 100}}}, {"id", 7}});
  ASSERT_TRUE(moved);
  EXPECT_EQ((*moved)["return"]["at_s"], 100.0) << moved->dump();
  EXPECT_TRUE(control->wait_event("OBJECT_MOVED", 5s, "name", "post"));
  for (const json& garbage : {json{{"execute", "move-object"}, {"arguments", {{"name", "post"}}}},
                              json{{"execute", "move-object"}, {"arguments", "post"}},
                              json{{"execute", "move-object"}, {"arguments", {{"name", "post"}, {"position_m", {1, 2, 3}}, {"at_s", "soon"}}}},
                              json{{"execute", "add-object"}, {"arguments", {{"object", 5}}}},
                              json{{"execute", "remove-object"}, {"arguments", {{"name", json::array()}}}}}) {
    const auto reply = control->execute(garbage);
    ASSERT_TRUE(reply) << garbage.dump();
    EXPECT_TRUE(reply->contains("error")) << garbage.dump() << " -> " << reply->dump();
  }
  const auto added = control->execute(
      {{"execute", "add-object"},
       {"arguments", {{"object", {{"name", "crate"}, {"sphere", {{"radius_m", 0.5}}}}}, {"at_s", 101}}}});
  ASSERT_TRUE(added && added->contains("return")) << (added ? added->dump() : "none");
  EXPECT_TRUE(control->wait_event("OBJECT_ADDED", 5s, "name", "crate"));
  const auto removed = control->execute({{"execute", "remove-object"}, {"arguments", {{"name", "crate"}, {"at_s", 102}}}});
  ASSERT_TRUE(removed && removed->contains("return")) << (removed ? removed->dump() : "none");
  EXPECT_TRUE(control->wait_event("OBJECT_REMOVED", 5s, "name", "crate"));
  auto host = TcpHost::connect(fd.daemon->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(reply_text(*host, "GET_STATUS"), "GET_STATUS reply 0000 0001");
}

}  // namespace
}  // namespace ldoem::daemon::test
