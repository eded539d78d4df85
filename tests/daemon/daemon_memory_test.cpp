// The daemon in-process on the memory endpoint: the test is the host, without a socket, a pty or
// the kernel's timing. Virtual time (D7) makes every test a fixed sequence of events; the same
// conversations over real sockets are in daemon_process_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

#include "daemon_process.hpp"
#include "host_link.hpp"
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
using base::SimTime;

constexpr auto kWallLimit = 30s;  // every wait is bounded; virtual time needs far less

// A daemon with only a memory endpoint (no CAN, TCP, serial or LPT), flash in memory.
struct InProcess {
  std::ostringstream out;
  std::ostringstream log;
  MemoryEndpoint* host = nullptr;
  std::unique_ptr<Daemon> daemon;
  std::string failure;

  explicit InProcess(const std::string& scene_text = minimal_scene_text(),
                     protocol::Transport kind = protocol::Transport::tcp,
                     std::optional<std::uint64_t> count_profiles = std::nullopt) {
    auto scene = scene::load_scene_from_string(scene_text, "scene.yaml");
    if (!scene) {
      failure = scene.error().message();
      return;
    }
    Options options;
    options.can_interface.reset();
    options.flash_mode = FlashMode::memory;
    options.virtual_time = true;
    options.log_level = LogLevel::info;
    options.count_profiles = count_profiles;
    auto memory = std::make_unique<MemoryEndpoint>(kind);
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

  // Sends `text` from connection `index` and runs until `count` telegrams came back.
  std::vector<MemoryEndpoint::Sent> exchange(std::uint32_t index, std::string_view text, std::size_t count = 1) {
    host->host_sends(index, telegram(text));
    return wait_for(count);
  }
  std::vector<MemoryEndpoint::Sent> wait_for(std::size_t count) {
    daemon->run_until([&] { return host->sent_count() >= count; }, kWallLimit);
    return host->take_sent();
  }
  std::string reply_text(std::uint32_t index, std::string_view text) {
    const auto sent = exchange(index, text);
    return sent.size() == 1 ? protocol::format_telegram(sent[0].payload) : "(" + std::to_string(sent.size()) + " replies)";
  }
};

TEST(DaemonMemory, StartsWithOneLinePerEndpointAndReady) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  EXPECT_EQ(d.out.str(), "memory\nready\n");
}

TEST(DaemonMemory, S1Conversation_AnswersEachStepAtTheRightSimulatedTime) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  EXPECT_EQ(d.reply_text(1, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  EXPECT_EQ(d.reply_text(1, "GET_FUNCTION 0001"), "GET_FUNCTION reply 0001 0001 0e10");
  // TRANS_ROTATE is answered when the head reaches speed (D7: about 2 s of simulated time).
  const auto rotate = d.exchange(1, "TRANS_ROTATE 0000");
  ASSERT_EQ(rotate.size(), 1u);
  EXPECT_EQ(protocol::format_telegram(rotate[0].payload), "TRANS_ROTATE reply 0000 0002");
  EXPECT_GT(rotate[0].at, SimTime(1500ms));
  EXPECT_LT(rotate[0].at, SimTime(2500ms));
  EXPECT_EQ(d.reply_text(1, "TRANS_MEASURE"), "TRANS_MEASURE reply 0000 0003 0000");
  const auto profiles = d.exchange(1, "GET_PROFILE 0003 39ff", 3);
  ASSERT_EQ(profiles.size(), 3u);
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    const auto profile = protocol::decode_profile(profiles[i].payload);
    ASSERT_TRUE(profile);
    EXPECT_EQ(profile->profile_sent, i + 1);
    if (i > 0) {
      EXPECT_EQ(profiles[i].at - profiles[i - 1].at, SimTime(100ms));  // 10 Hz
    }
  }
  EXPECT_EQ(d.daemon->counters().profiles_sent, 3u);
  EXPECT_EQ(d.daemon->counters().telegrams_received, 5u);
}

TEST(DaemonMemory, TwoConnections_ProfilesGoOnlyToTheOneThatAsked) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "TRANS_ROTATE 0000");
  d.exchange(1, "TRANS_MEASURE");
  const auto profiles = d.exchange(1, "GET_PROFILE 0002 39ff", 2);
  ASSERT_EQ(profiles.size(), 2u);
  for (const auto& sent : profiles) EXPECT_EQ(sent.index, 1u);
  EXPECT_EQ(d.reply_text(2, "GET_STATUS"), "GET_STATUS reply 0000 0003");
}

TEST(DaemonMemory, BusyConnection_SkipsProfilesAndCountsThem) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "TRANS_ROTATE 0000");
  d.exchange(1, "TRANS_MEASURE");
  d.exchange(1, "GET_PROFILE 0000 39ff", 2);
  d.host->set_busy(1, true);
  const SimTime busy_from = d.daemon->now();
  d.daemon->run_until([&] { return d.daemon->now() >= busy_from + SimTime(1s); }, kWallLimit);
  EXPECT_EQ(d.host->sent_count(), 0u);
  EXPECT_GE(d.daemon->counters().skipped_profiles, 9u);  // D10: ten revolutions, none sent
  d.host->set_busy(1, false);
  const auto after = d.wait_for(1);
  ASSERT_EQ(after.size(), 1u);
  const auto profile = protocol::decode_profile(after[0].payload);
  ASSERT_TRUE(profile);
  EXPECT_EQ(profile->profile_sent, 3);  // PROFILESENT goes on where it stopped, PROFILECOUNT jumped
}

TEST(DaemonMemory, ClosedConnection_LeavesNoTimerThatMovesTheVirtualClock) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "TRANS_ROTATE 0000");
  d.exchange(1, "TRANS_MEASURE");
  d.exchange(1, "GET_PROFILE 0000 39ff", 1);
  d.host->host_closes(1);
  const SimTime closed_at = d.daemon->now();
  int rounds = 0;
  d.daemon->run_until([&] { return ++rounds > 5; }, kWallLimit);
  // The revolution timer was cancelled: with nothing queued the virtual clock stands still (D7).
  EXPECT_EQ(d.daemon->now(), closed_at);
  EXPECT_EQ(d.host->sent_count(), 0u);
}

TEST(DaemonMemory, FramingError_IsAnsweredServiceFailure) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.host->host_sends_bad_frame(1, protocol::FramingError{protocol::DecodeError::bad_header, 0x0101});
  const auto sent = d.wait_for(1);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(protocol::format_telegram(sent[0].payload), "SERVICE_FAILURE 0101 0005");  // D2
  EXPECT_EQ(d.daemon->counters().framing_errors, 1u);
}

TEST(DaemonMemory, CountersLine_NamesEveryCounter) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "GET_STATUS");
  const std::string line = format_counters(d.daemon->counters());
  EXPECT_NE(line.find("telegrams_received=1 "), std::string::npos) << line;
  EXPECT_NE(line.find("lpt_steps=0"), std::string::npos) << line;
}

// The range straight ahead (first point of the first sector) of the next profile.
std::optional<std::uint16_t> distance_ahead(InProcess& d) {
  const auto sent = d.exchange(1, "GET_PROFILE 0001 39ff");
  if (sent.size() != 1) return std::nullopt;
  const auto profile = protocol::decode_profile(sent[0].payload);
  if (!profile) return std::nullopt;
  return distance_at_angle_zero(*profile);
}

TEST(DaemonMemory, StepperRegisterWrites_TiltTheBeamInLaterProfiles) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "TRANS_ROTATE 0000");
  d.exchange(1, "TRANS_MEASURE");
  EXPECT_EQ(distance_ahead(d), std::optional<std::uint16_t>(1280));  // level: 5 m
  const SimTime at = d.daemon->now();
  for (int i = 0; i < 200; ++i) {  // D8: 200 full steps with DIR = 1: 18 deg up
    d.daemon->device().on_register_write(at, 0x01);
    d.daemon->device().on_register_write(at, 0x03);
  }
  const auto tilted = distance_ahead(d);
  ASSERT_TRUE(tilted);
  EXPECT_NEAR(*tilted, 5.0 / std::cos(18.0 * std::numbers::pi / 180.0) * 256.0, 1.0);  // 5.257 m
  EXPECT_EQ(d.daemon->counters().lpt_steps, 200u);
}

TEST(DaemonMemory, CountProfiles_StopsTheLoopAfterThatMany) {
  InProcess d(minimal_scene_text(), protocol::Transport::tcp, 2);
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "TRANS_ROTATE 0000");
  d.exchange(1, "TRANS_MEASURE");
  d.host->host_sends(1, telegram("GET_PROFILE 0000 39ff"));
  const auto started = std::chrono::steady_clock::now();
  EXPECT_FALSE(d.daemon->run_until([] { return false; }, kWallLimit));  // returns when the loop stops
  EXPECT_LT(std::chrono::steady_clock::now() - started, kWallLimit);
  EXPECT_EQ(d.host->sent_count(), 2u);
  EXPECT_EQ(d.daemon->counters().profiles_sent, 2u);
}

TEST(DaemonMemory, InfoLog_NamesEachRequestAndReplyInTextForm) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  d.exchange(1, "GET_STATUS");
  const std::string text = d.log.str();
  EXPECT_NE(text.find("ldoem-emud: info: tcp#1 -> GET_STATUS\n"), std::string::npos) << text;
  EXPECT_NE(text.find("ldoem-emud: info: tcp#1 <- GET_STATUS reply 0000 0001\n"), std::string::npos) << text;
}

TEST(DaemonMemory, CanConfigChange_IsPassedToTheEndpointsOnceAfterItsReply) {
  InProcess d(minimal_scene_text(), protocol::Transport::can);
  ASSERT_TRUE(d.daemon) << d.failure;
  EXPECT_EQ(d.reply_text(1, "SET_CONFIG 0002 0004 0700 0701 0000 0000"), "SET_CONFIG reply 0000");
  ASSERT_EQ(d.host->can_configs().size(), 1u);  // D1: the daemon is told, it compares nothing
  EXPECT_EQ(d.host->can_configs()[0].request_id, 0x700);
  EXPECT_EQ(d.host->can_configs()[0].response_id, 0x701);
  d.exchange(1, "GET_STATUS");
  EXPECT_EQ(d.host->can_configs().size(), 1u);
}

// ----------------------------------------------------------------------------------- wire tap

struct CollectingTap final : endpoints::WireTap {
  std::vector<endpoints::WireTelegram> seen;
  bool drop_replies = false;
  bool corrupt_requests = false;
  endpoints::WireVerdict on_telegram(endpoints::WireTelegram& telegram) override {
    seen.push_back(telegram);
    if (telegram.direction == protocol::WireDirection::host_to_device && corrupt_requests) {
      telegram.payload[1] = 0x7F;  // an unknown service (D2 reason 1)
    }
    if (telegram.direction == protocol::WireDirection::device_to_host && drop_replies) return endpoints::WireVerdict::drop;
    return endpoints::WireVerdict::pass;
  }
};

TEST(DaemonWireTap, SeesEveryTelegramInAndOut) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  CollectingTap tap;
  d.daemon->device().set_wire_tap(&tap);
  EXPECT_EQ(d.reply_text(3, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  ASSERT_EQ(tap.seen.size(), 2u);
  EXPECT_EQ(tap.seen[0].direction, protocol::WireDirection::host_to_device);
  EXPECT_EQ(tap.seen[0].connection, (protocol::ConnectionId{protocol::Transport::tcp, 3}));
  EXPECT_EQ(protocol::format_telegram(tap.seen[0].payload), "GET_STATUS");
  EXPECT_EQ(tap.seen[1].direction, protocol::WireDirection::device_to_host);
  EXPECT_EQ(protocol::format_telegram(tap.seen[1].payload), "GET_STATUS reply 0000 0001");
  EXPECT_FALSE(tap.seen[1].is_profile);
}

TEST(DaemonWireTap, DroppedReply_NeverReachesTheHost_AndAlteredRequestIsWhatTheDeviceSees) {
  InProcess d;
  ASSERT_TRUE(d.daemon) << d.failure;
  CollectingTap tap;
  d.daemon->device().set_wire_tap(&tap);
  tap.drop_replies = true;
  d.host->host_sends(1, telegram("GET_STATUS"));
  int rounds = 0;
  d.daemon->run_until([&] { return ++rounds > 3; }, kWallLimit);
  EXPECT_EQ(d.host->sent_count(), 0u);
  EXPECT_EQ(d.daemon->counters().telegrams_received, 1u);
  tap.drop_replies = false;
  tap.corrupt_requests = true;
  EXPECT_EQ(d.reply_text(1, "GET_STATUS"), "SERVICE_FAILURE 017f 0001");
}

}  // namespace
}  // namespace ldoem::daemon::test
