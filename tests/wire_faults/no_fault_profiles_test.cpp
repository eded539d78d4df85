// Issue 10: "a scene without faults gives byte-identical profiles to today's". A conversation
// with profiles on the paper's corridor (TCP, --virtual-time) hashes to the digest that the
// daemon from before the fault work (commit bda8823, the last before the D11 catalogue) gave for
// the same conversation; and the same scene with endpoint and beam faults that never act gives it
// too. (Never: triggered by a request nobody sends. An `at_s` trigger is no dormant fault under
// --virtual-time: a daemon with nothing to do jumps its clock to the next deadline, that one too.)
// To check against a build of that commit rather than the recorded digest:
//   LDOEM_BASELINE_EMUD=/path/to/old/ldoem-emud ctest -R NoFaultProfiles
// (scripts/bench-wire-fault-hook.sh --baseline compares whole paper scans the same way.)
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "wire_fault_support.hpp"

namespace ldoem::wire_faults::test {
namespace {

using namespace std::chrono_literals;
using daemon::test::TcpHost;
using daemon::test::telegram;

// What ldoem-emud at bda8823 answered to `conversation` below on scenes/corridor.yaml.
constexpr std::uint64_t kDigestBeforeTheFaultWork = 0x840317bba875ee2bULL;

std::string corridor_scene() {
  std::ifstream file(std::string(LDOEM_SOURCE_DIR) + "/scenes/corridor.yaml");
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// FNV-1a over every byte the daemon sent, frame by frame; and how many frames came.
struct Transcript {
  std::uint64_t digest = 0xcbf29ce484222325ULL;
  int frames = 0;
};

// GET_STATUS, spin up, measure, 16 profiles of every field, GET_STATUS: every frame it answers.
Transcript conversation(DaemonProcess& daemon) {
  Transcript transcript;
  if (!daemon.wait_ready()) return transcript;
  auto host = TcpHost::connect(daemon.tcp_port());
  if (!host) return transcript;
  auto take = [&](int frames) {
    for (int i = 0; i < frames; ++i) {
      const auto frame = host->next_frame(10s);
      if (!frame) return;
      for (const std::uint8_t byte : *frame) {
        transcript.digest ^= byte;
        transcript.digest *= 0x100000001b3ULL;
      }
      ++transcript.frames;
    }
  };
  for (const auto& [request, frames] : {std::pair{"GET_STATUS", 1}, {"TRANS_ROTATE 0000", 1}, {"TRANS_MEASURE", 1},
                                        {"GET_PROFILE 0010 39ff", 16}, {"GET_STATUS", 1}}) {
    host->send(telegram(request));
    take(frames);
  }
  daemon.signal(SIGTERM);
  daemon.wait();
  return transcript;
}

std::vector<std::string> daemon_arguments(const TempDir& dir, const std::string& scene_text) {
  return {"--scene", dir.write("scene.yaml", scene_text), "--tcp", "tcp:127.0.0.1:0", "--no-can", "--no-flash",
          "--virtual-time", "--timeout", "100"};
}

TEST(NoFaultProfiles, ACorridorConversationGivesTheBytesOfTheDaemonBeforeTheFaultWork) {
  TempDir dir;
  auto plain = DaemonProcess::start(daemon_arguments(dir, corridor_scene()));
  ASSERT_TRUE(plain);
  const Transcript today = conversation(*plain);
  EXPECT_EQ(today.frames, 20) << plain->stderr_text();

  TempDir dormant_dir;
  auto dormant = DaemonProcess::start(daemon_arguments(
      dormant_dir, corridor_scene() + "faults:\n  - {kind: garbage, on: {service: GET_SYNC_CLOCK, nth: 1}}\n"
                                      "  - {kind: corrupt_checksum, on: {service: GET_SYNC_CLOCK, nth: 1}}\n"
                                      "  - {kind: bandwidth, on: {service: GET_SYNC_CLOCK, nth: 1}}\n"
                                      "  - {kind: blind, from_deg: 10, to_deg: 20, on: {service: GET_SYNC_CLOCK, nth: 1}}\n"
                                      "  - {kind: window_dirt, fraction: 0.5, on: {service: GET_SYNC_CLOCK, nth: 1}}\n"));
  ASSERT_TRUE(dormant);
  const Transcript with_dormant_faults = conversation(*dormant);
  EXPECT_EQ(with_dormant_faults.frames, 20) << dormant->stderr_text();
  EXPECT_EQ(with_dormant_faults.digest, today.digest);

  if (const char* baseline = std::getenv("LDOEM_BASELINE_EMUD"); baseline != nullptr && *baseline != '\0') {
    TempDir baseline_dir;
    auto old = DaemonProcess::start_program(baseline, daemon_arguments(baseline_dir, corridor_scene()));
    ASSERT_TRUE(old);
    const Transcript before = conversation(*old);
    EXPECT_EQ(before.frames, 20) << old->stderr_text();
    EXPECT_EQ(today.digest, before.digest) << "baseline " << baseline << ": 0x" << std::hex << before.digest;
  }
  EXPECT_EQ(today.digest, kDigestBeforeTheFaultWork) << "0x" << std::hex << today.digest;
}

}  // namespace
}  // namespace ldoem::wire_faults::test
