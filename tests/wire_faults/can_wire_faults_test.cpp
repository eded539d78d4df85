// D11 wire faults on CAN (D1: ISO-TP over CAN 2.0A), produced inside the CAN endpoint, on a real
// vcan0 inside User-Mode Linux (label vcan; they FAIL, never skip, without vcan0):
//   scripts/uml/run.sh -- ctest --test-dir build/default -L vcan -R wire_faults --output-on-failure
// The test is the host on CAN_RAW and sees every frame: the first consecutive frame dropped,
// repeated or mis-numbered, garbage as stray frames, FC overflow and FC WAIT on its first frame;
// and libldoem's reaction (FC overflow is the typed error `refused`, WAIT is waited out).
#include <gtest/gtest.h>

#include <signal.h>

#include <fstream>
#include <sstream>

#include "ldoem/driver/transport.hpp"
#include "ldoem/endpoints/isotp_channel.hpp"
#include "ldoem/faults/fault_scheduler.hpp"
#include "ldoem/io/can_interface.hpp"
#include "ldoem/io/can_socket.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/profile.hpp"
#include "wire_fault_support.hpp"

namespace ldoem::wire_faults::test {
namespace {

using namespace std::chrono_literals;
using daemon::test::minimal_scene_text;
using daemon::test::telegram;
using protocol::CanFrame;

#define LDOEM_REQUIRE_VCAN0()                                                                  \
  do {                                                                                         \
    auto vcan = io::check_can_interface("vcan0");                                              \
    ASSERT_TRUE(vcan) << vcan.error().message()                                                \
                      << " (vcan tests run inside UML: scripts/uml/run.sh -- ctest -L vcan)";  \
  } while (false)

CanFrame frame(std::uint32_t id, protocol::Bytes bytes) { return *protocol::make_can_frame(id, bytes); }

std::string text(const std::vector<CanFrame>& frames) {
  std::string out;
  for (const CanFrame& f : frames) out += daemon::test::to_hex(f.payload()) + "\n";
  return out;
}

// The host on CAN_RAW: sends frames on 0x6C0, sees every frame on 0x6C1.
class RawHost {
 public:
  RawHost() {
    auto opened = io::CanRawSocket::open("vcan0", std::vector<io::CanIdFilter>{io::exact_standard_id(0x6C1)});
    EXPECT_TRUE(opened) << opened.error().message();
    if (opened) socket_.emplace(std::move(*opened));
  }
  void send(protocol::Bytes bytes) {
    ASSERT_TRUE(socket_);
    ASSERT_TRUE(socket_->send(frame(0x6C0, std::move(bytes))));
  }
  // Frames until none came for `quiet` (or `limit` passed).
  std::vector<CanFrame> collect(std::chrono::milliseconds quiet = 400ms, std::chrono::milliseconds limit = 10s) {
    std::vector<CanFrame> frames;
    const auto give_up = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < give_up && socket_ && daemon::test::wait_readable(socket_->fd(), quiet)) {
      while (auto received = socket_->receive()) {
        if (!received->has_value()) break;
        frames.push_back(**received);
      }
    }
    return frames;
  }
  // The next frame within `limit`.
  std::optional<CanFrame> next(std::chrono::milliseconds limit = 5s) {
    if (!socket_ || !daemon::test::wait_readable(socket_->fd(), limit)) return std::nullopt;
    auto received = socket_->receive();
    if (!received || !received->has_value()) return std::nullopt;
    return **received;
  }

 private:
  std::optional<io::CanRawSocket> socket_;
};

std::vector<std::string> can_daemon_arguments() { return {"--can", "can:vcan0"}; }

// CAN daemons run on the wall clock: FC WAIT every 0.5 s of real time, as a host sees it.
struct CanFaultyDaemon : FaultyDaemon {
  explicit CanFaultyDaemon(const std::string& scene_text) : FaultyDaemon(scene_text, can_daemon_arguments(), false) {}
};

std::string scene_with(const std::string& faults) { return minimal_scene_text() + "seed: 7\nfaults:\n" + faults; }

// GET_IDENTIFICATION 0x00 is answered in two frames, `10 09 81 01 ...` and, after our FC, one
// consecutive frame `21 ...` (messages with more are in tests/endpoints/isotp_channel_faults_test.cpp).
std::vector<CanFrame> ask_identification(RawHost& host) {
  host.send({0x04, 0x01, 0x01, 0x00, 0x00});
  const auto first = host.next();
  if (!first) return {};
  std::vector<CanFrame> frames{*first};
  if (protocol::isotp_frame_type(*first) == protocol::IsoTpFrameType::first_frame) {
    host.send({0x30, 0x00, 0x00});
    const auto rest = host.collect();
    frames.insert(frames.end(), rest.begin(), rest.end());
  }
  return frames;
}

// Runs `kind` on the first GET_IDENTIFICATION; returns (faulted reply, the healthy one after it).
std::pair<std::vector<CanFrame>, std::vector<CanFrame>> identification_with(const std::string& fault_entry) {
  CanFaultyDaemon d(scene_with(fault_entry));
  EXPECT_TRUE(d.ready()) << d.diagnostics();
  RawHost host;
  auto faulted = ask_identification(host);
  auto healthy = ask_identification(host);
  return {faulted, healthy};
}

TEST(WireFaultsCan, IsotpDropCf_TheFirstConsecutiveFrameIsNotSent) {
  LDOEM_REQUIRE_VCAN0();
  auto [faulted, healthy] = identification_with("  - {kind: isotp_drop_cf, on: {service: GET_IDENTIFICATION, nth: 1}}\n");
  ASSERT_GE(healthy.size(), 2u) << text(healthy);
  EXPECT_EQ(healthy[1].data[0], 0x21);
  std::vector<CanFrame> expected = healthy;
  expected.erase(expected.begin() + 1);
  EXPECT_EQ(text(faulted), text(expected));
}

TEST(WireFaultsCan, IsotpRepeatCf_TheFirstConsecutiveFrameIsSentTwice) {
  LDOEM_REQUIRE_VCAN0();
  auto [faulted, healthy] = identification_with("  - {kind: isotp_repeat_cf, on: {service: GET_IDENTIFICATION, nth: 1}}\n");
  ASSERT_GE(healthy.size(), 2u) << text(healthy);
  std::vector<CanFrame> expected = healthy;
  expected.insert(expected.begin() + 1, healthy[1]);
  EXPECT_EQ(text(faulted), text(expected));
}

TEST(WireFaultsCan, IsotpBadSn_TheFirstConsecutiveFrameCarriesSequenceTwo) {
  LDOEM_REQUIRE_VCAN0();
  auto [faulted, healthy] = identification_with("  - {kind: isotp_bad_sn, on: {service: GET_IDENTIFICATION, nth: 1}}\n");
  ASSERT_GE(healthy.size(), 2u) << text(healthy);
  std::vector<CanFrame> expected = healthy;
  expected[1].data[0] = 0x22;
  EXPECT_EQ(text(faulted), text(expected));
}

TEST(WireFaultsCan, IsotpBadSn_LibldoemDropsTheMessageCountsItAndTheRetryIsAnswered) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_bad_sn, on: {service: GET_IDENTIFICATION, nth: 1}}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = driver::open_transport(*driver::parse_endpoint("can:vcan0"));
  ASSERT_TRUE(transport);
  ASSERT_TRUE((*transport)->send(telegram("GET_IDENTIFICATION 0001"), driver::Clock::now() + 2s));
  const auto lost = (*transport)->receive(driver::Clock::now() + 1500ms);
  ASSERT_FALSE(lost);
  EXPECT_EQ(lost.error().kind, driver::ErrorKind::timeout);
  EXPECT_TRUE(driver::is_retryable(lost.error()));
  EXPECT_GE((*transport)->counters().dropped_frames, 1u);
  ASSERT_TRUE((*transport)->send(telegram("GET_IDENTIFICATION 0001"), driver::Clock::now() + 2s));
  const auto reply = (*transport)->receive(driver::Clock::now() + 5s);
  ASSERT_TRUE(reply);
  EXPECT_EQ(protocol::format_telegram(*reply), "GET_IDENTIFICATION reply 4c44 2d4f 454d 3130 3030");
}

TEST(WireFaultsCan, Garbage_StrayConsecutiveFramesBeforeTheReply) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: garbage, bytes: 10, on: {service: GET_STATUS, nth: 1}}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawHost host;
  host.send({0x02, 0x01, 0x02});
  std::vector<CanFrame> expected = endpoints::garbage_frames(0x6C1, faults::fault_garbage(7, 1, 10));
  ASSERT_EQ(expected.size(), 2u);
  expected.push_back(frame(0x6C1, {0x06, 0x81, 0x02, 0x00, 0x00, 0x00, 0x01}));
  EXPECT_EQ(text(host.collect()), text(expected));
}

TEST(WireFaultsCan, Garbage_LibldoemSkipsStrayFramesAndReadsTheTelegram) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: garbage, bytes: 16, on: {service: GET_STATUS, nth: 1}}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = driver::open_transport(*driver::parse_endpoint("can:vcan0"));
  ASSERT_TRUE(transport);
  ASSERT_TRUE((*transport)->send(telegram("GET_STATUS"), driver::Clock::now() + 2s));
  const auto reply = (*transport)->receive(driver::Clock::now() + 5s);
  ASSERT_TRUE(reply);
  EXPECT_EQ(protocol::format_telegram(*reply), "GET_STATUS reply 0000 0001");
}

// SET_FUNCTION with its three parameters is 8 bytes: a first frame and one consecutive frame.
const protocol::Bytes kLongRequestFirstFrame{0x10, 0x08, 0x02, 0x0A, 0x00, 0x01, 0x00, 0x01};

TEST(WireFaultsCan, IsotpFcOverflow_TheHostsFirstFrameIsAnswered3200_LibldoemSaysRefused) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_fc_overflow, count: 2}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  {
    RawHost host;
    host.send(kLongRequestFirstFrame);
    EXPECT_EQ(text(host.collect()), "32 00 00\n");
  }
  auto transport = driver::open_transport(*driver::parse_endpoint("can:vcan0"));
  ASSERT_TRUE(transport);
  const auto refused = (*transport)->send(telegram("SET_FUNCTION 0001 0001 0e10"), driver::Clock::now() + 5s);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().kind, driver::ErrorKind::refused);
  EXPECT_FALSE(driver::is_retryable(refused.error()));
  // The count is used up: the same request goes through.
  ASSERT_TRUE((*transport)->send(telegram("SET_FUNCTION 0001 0001 0e10"), driver::Clock::now() + 5s));
  EXPECT_TRUE((*transport)->receive(driver::Clock::now() + 5s));
}

TEST(WireFaultsCan, IsotpFcWait_WaitEveryHalfSecondWhileActiveThenContinueToSend) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_fc_wait, duration_s: 1.2, on: {service: SET_FUNCTION, nth: 1}}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawHost host;
  host.send(kLongRequestFirstFrame);  // starts the fault (0 .. 1.2 s) and is held by it
  // Held with WAIT at once, 0.5 and 1.0 s later; at 1.5 s the fault is over: continue to send.
  EXPECT_EQ(text(host.collect(1500ms)), "31 00 00\n31 00 00\n31 00 00\n30 00 00\n");
}

TEST(WireFaultsCan, IsotpFcWait_LibldoemWaitsItOutAndGetsTheReply) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_fc_wait, duration_s: 1.2, on: {service: SET_FUNCTION, nth: 1}}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = driver::open_transport(*driver::parse_endpoint("can:vcan0"));
  ASSERT_TRUE(transport);
  // The first frame starts the fault and is held by it.
  ASSERT_TRUE((*transport)->send(telegram("SET_FUNCTION 0001 0001 0e10"), driver::Clock::now() + 10s));
  EXPECT_TRUE((*transport)->receive(driver::Clock::now() + 5s));
}

TEST(WireFaultsCan, IsotpFcWait_EndlessUntilTheHostGivesUp_LibldoemTimesOut) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_fc_wait}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto transport = driver::open_transport(*driver::parse_endpoint("can:vcan0"));
  ASSERT_TRUE(transport);
  const auto waited = (*transport)->send(telegram("SET_FUNCTION 0001 0001 0e10"), driver::Clock::now() + 2s);
  ASSERT_FALSE(waited);
  EXPECT_EQ(waited.error().kind, driver::ErrorKind::timeout);
  // A single-frame request is not held: the device still answers.
  ASSERT_TRUE((*transport)->send(telegram("GET_STATUS"), driver::Clock::now() + 2s));
  const auto reply = (*transport)->receive(driver::Clock::now() + 5s);
  ASSERT_TRUE(reply);
  EXPECT_EQ(protocol::format_telegram(*reply), "GET_STATUS reply 0000 0001");
}

// ------------------------------------------------------------- the service of a multi-frame request

// SET_FUNCTION 0001 0001 0e10's consecutive frame, after kLongRequestFirstFrame.
const protocol::Bytes kLongRequestConsecutiveFrame{0x21, 0x0E, 0x10};
// GET_STATUS with six bytes too many: a request of eight bytes, sent as a first frame.
const protocol::Bytes kLongGetStatusFirstFrame{0x10, 0x08, 0x01, 0x02, 0x00, 0x00, 0x00, 0x00};

// isotp_fc_overflow and isotp_fc_wait act on a host's first frame; the service it carries decides
// whether the fault's `service` matches, and the request is counted by an `on`/`every` trigger of
// those kinds at that first frame, so that `on: {service: SET_FUNCTION, nth: 2}` holds the second
// SET_FUNCTION itself (issue 10: the trigger used to count it only once complete, and the fault
// then fell on whichever first frame came next, whatever its service).
TEST(WireFaultsCan, IsotpFcOverflow_OnlyFirstFramesOfTheNamedService) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_fc_overflow, count: 1, service: SET_FUNCTION}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawHost host;
  host.send(kLongGetStatusFirstFrame);  // another service: flow control as usual
  EXPECT_EQ(text(host.collect()), "30 00 00\n");
  host.send({0x21, 0x00, 0x00});
  EXPECT_FALSE(host.collect().empty());  // answered (a service failure: too long a GET_STATUS)
  host.send(kLongRequestFirstFrame);
  EXPECT_EQ(text(host.collect()), "32 00 00\n");
  host.send(kLongRequestFirstFrame);  // the count is used up
  EXPECT_EQ(text(host.collect()), "30 00 00\n");
}

TEST(WireFaultsCan, IsotpFcWait_OnTheNthRequestHoldsThatRequestsFirstFrame) {
  LDOEM_REQUIRE_VCAN0();
  CanFaultyDaemon d(scene_with("  - {kind: isotp_fc_wait, duration_s: 0.7, on: {service: SET_FUNCTION, nth: 2}}\n"));
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawHost host;
  host.send(kLongGetStatusFirstFrame);  // another service: not counted, not held
  EXPECT_EQ(text(host.collect()), "30 00 00\n");
  host.send({0x21, 0x00, 0x00});
  EXPECT_FALSE(host.collect().empty());
  host.send(kLongRequestFirstFrame);  // SET_FUNCTION 1
  EXPECT_EQ(text(host.collect()), "30 00 00\n");
  host.send(kLongRequestConsecutiveFrame);
  EXPECT_FALSE(host.collect().empty());
  host.send(kLongRequestFirstFrame);  // SET_FUNCTION 2: held at once, WAIT again at 0.5 s, then go on
  EXPECT_EQ(text(host.collect(1000ms)), "31 00 00\n31 00 00\n30 00 00\n");
  EXPECT_NE(d.events().find("\"reason\":\"scene[0] on\""), std::string::npos) << d.events();
}

// ------------------------------------------------------------------ isotp_fc_wait and virtual time

// An endless isotp_fc_wait under --virtual-time: the WAITs are due every 0.5 s of simulated time,
// and a virtual clock jumps to them as soon as nothing else happens; each WAIT now gives the host
// the daemon's wall-clock grace (a real host needs wall time to answer it), so the daemon sends
// about one a second instead of flooding the bus as fast as it can.
TEST(WireFaultsCan, IsotpFcWait_EndlessUnderVirtualTimeSendsBoundedWaits) {
  LDOEM_REQUIRE_VCAN0();
  FaultyDaemon d(scene_with("  - {kind: isotp_fc_wait}\n"), can_daemon_arguments(), true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawHost host;
  host.send(kLongRequestFirstFrame);
  std::vector<CanFrame> frames;
  const auto until = std::chrono::steady_clock::now() + 3s;
  while (std::chrono::steady_clock::now() < until && frames.size() < 10000) {
    if (auto next = host.next(100ms)) frames.push_back(*next);
  }
  EXPECT_GE(frames.size(), 2u) << text(frames);
  EXPECT_LE(frames.size(), 5u) << frames.size() << " frames in 3 s";
  for (const CanFrame& f : frames) EXPECT_EQ(daemon::test::to_hex(f.payload()), "31 00 00");
  // The host gives up: a new request ends the hold and is answered.
  host.send({0x02, 0x01, 0x02});
  EXPECT_EQ(text(host.collect()), "06 81 02 00 00 00 01\n");
}

// ----------------------------------------------------------------------------------- determinism

// Same scene, seed and conversation on CAN (--virtual-time): the same frames on the bus and the
// same event log, twice, with probability-triggered faults (garbage, drop_reply, isotp_repeat_cf,
// isotp_fc_overflow at the first frame) and a counted one (isotp_bad_sn, count 2, every 3rd).
TEST(WireFaultsCan, SameSeedAndConversationGiveTheSameFramesAndEventsTwice) {
  LDOEM_REQUIRE_VCAN0();
  const std::string scene = minimal_scene_text() + "seed: 5\nfaults:\n"
                            "  - {kind: garbage, bytes: 5, probability: 0.3, service: GET_STATUS}\n"
                            "  - {kind: drop_reply, probability: 0.25, service: GET_STATUS}\n"
                            "  - {kind: isotp_repeat_cf, probability: 0.3, service: GET_IDENTIFICATION}\n"
                            "  - {kind: isotp_bad_sn, count: 2, every: {service: GET_IDENTIFICATION, count: 3}}\n"
                            "  - {kind: isotp_fc_overflow, probability: 0.4, service: SET_FUNCTION}\n";
  auto run = [&scene] {
    FaultyDaemon d(scene, can_daemon_arguments(), true);
    EXPECT_TRUE(d.ready()) << d.diagnostics();
    RawHost host;
    std::string transcript;
    auto note = [&transcript](std::string_view what, const std::vector<CanFrame>& frames) {
      transcript += std::string(what) + " ->\n" + (frames.empty() ? std::string("(nothing)\n") : text(frames));
    };
    for (int round = 0; round < 8; ++round) {
      host.send({0x02, 0x01, 0x02});
      note("GET_STATUS", host.collect(300ms));
      note("GET_IDENTIFICATION", ask_identification(host));
      host.send(kLongRequestFirstFrame);
      const auto flow_control = host.collect(300ms);
      note("SET_FUNCTION first frame", flow_control);
      if (text(flow_control) == "30 00 00\n") {
        host.send(kLongRequestConsecutiveFrame);
        note("SET_FUNCTION", host.collect(300ms));
      }
    }
    d.process->signal(SIGTERM);
    d.process->wait();
    return std::pair{transcript, d.events()};
  };
  const auto first = run_twice_expect_same(run);
  // Each fault acted at least once, and not on every request.
  for (const char* kind : {"garbage", "drop_reply", "isotp_repeat_cf", "isotp_bad_sn", "isotp_fc_overflow"}) {
    EXPECT_NE(first.second.find("\"kind\":\"" + std::string(kind) + "\""), std::string::npos) << kind << "\n" << first.second;
  }
  EXPECT_NE(first.first.find("SET_FUNCTION first frame ->\n32 00 00\n"), std::string::npos) << first.first;
  EXPECT_NE(first.first.find("SET_FUNCTION first frame ->\n30 00 00\n"), std::string::npos) << first.first;
  EXPECT_NE(first.first.find("GET_STATUS ->\n(nothing)\n"), std::string::npos) << first.first;
  EXPECT_NE(first.first.find("GET_STATUS ->\n06 81 02 00 00 00 01\n"), std::string::npos) << first.first;
}

// scenes/faults/lossy-can.yaml as its header says: libldoem drops each broken message (a lost or
// repeated consecutive frame), times out on that request and asks again; every profile it
// returns decodes, none is assembled from frames of two messages.
TEST(WireFaultsCan, LossyCanScenario_LibldoemRetriesEveryBrokenProfile) {
  LDOEM_REQUIRE_VCAN0();
  std::ifstream file(std::string(LDOEM_SOURCE_DIR) + "/scenes/faults/lossy-can.yaml");
  std::stringstream scene;
  scene << file.rdbuf();
  ASSERT_FALSE(scene.str().empty());
  CanFaultyDaemon d(scene.str());
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto opened = driver::open_transport(*driver::parse_endpoint("can:vcan0"));
  ASSERT_TRUE(opened);
  driver::TelegramTransport& transport = **opened;
  auto ask = [&](std::string_view request, std::chrono::milliseconds limit) -> std::optional<protocol::Bytes> {
    if (!transport.send(telegram(request), driver::Clock::now() + 2s)) return std::nullopt;
    auto reply = transport.receive(driver::Clock::now() + limit);
    if (!reply) {
      EXPECT_TRUE(driver::is_retryable(reply.error())) << driver::describe(reply.error());
      return std::nullopt;
    }
    return *reply;
  };
  ASSERT_TRUE(ask("TRANS_ROTATE 0000", 10s));
  ASSERT_TRUE(ask("TRANS_MEASURE", 5s));
  constexpr int kProfiles = 30;
  int retries = 0;
  std::uint32_t last_profile_number = 0;
  for (int i = 0; i < kProfiles; ++i) {
    std::optional<protocol::Bytes> reply;
    for (int attempt = 0; attempt < 4 && !reply; ++attempt) {
      reply = ask("GET_PROFILE 0001 39ff", 1500ms);
      if (!reply) ++retries;
    }
    ASSERT_TRUE(reply) << "profile " << i << " lost four times";
    const auto profile = protocol::decode_profile(*reply);
    ASSERT_TRUE(profile) << daemon::test::to_hex(*reply);
    EXPECT_GT(profile->profile_count, last_profile_number);
    last_profile_number = profile->profile_count;
  }
  EXPECT_GE(retries, 1);  // the 25th GET_PROFILE's reply repeats a consecutive frame at least
  EXPECT_GE(transport.counters().dropped_frames, static_cast<std::uint64_t>(retries));
  EXPECT_NE(d.events().find("\"kind\":\"isotp_repeat_cf\""), std::string::npos) << d.events();
}

}  // namespace
}  // namespace ldoem::wire_faults::test
