// The kernel's ISO-TP (CAN_ISOTP) against the daemon, in the gpio UML kernel only (label gpio:
// the plain UML kernel has no CAN_ISOTP). D1 says ours must interoperate with it:
//   - can-utils isotpsend/isotprecv (kernel sockets) get every reply, including the 2.2 kB
//     (0x39FF) and 4.4 kB (0x3DFF) profiles of the D4 sector table: the 12-bit and the 32-bit
//     first frame (over 4095 bytes), flow control and 300+ consecutive frames;
//   - ldoem-scan --device can:isotp:vcan0 (libldoem's kernel transport) gives a cloud
//     byte-identical to the user-space path (can:vcan0).
#include <gtest/gtest.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/isotp.h>

#include <sstream>
#include <thread>

#include "corridor_expectations.hpp"
#include "corridor_scan.hpp"

namespace ldoem::e2e {
namespace {

bool kernel_has_isotp() {
  const int fd = ::socket(PF_CAN, SOCK_DGRAM, CAN_ISOTP);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

#define LDOEM_REQUIRE_KERNEL_ISOTP()                                                                  \
  ASSERT_NE(if_nametoindex("vcan0"), 0U) << "no vcan0: run inside scripts/uml/run.sh --kernel ... --gpio"; \
  ASSERT_TRUE(kernel_has_isotp()) << "no CAN_ISOTP: run in the gpio UML kernel (scripts/uml/build-gpio-kernel.sh)"

// The hex lines isotprecv has printed so far (one message per line), whole lines only: a long
// profile's line (13 kB of hex) leaves isotprecv's stdio buffer in pieces, and a busy machine
// let the test read between two of them (1707 of 4364 bytes once).
std::vector<std::string> received_lines(const ChildProcess& receiver) {
  std::vector<std::string> lines;
  std::string output = receiver.stdout_text();
  const auto last_newline = output.rfind('\n');
  output.resize(last_newline == std::string::npos ? 0 : last_newline + 1);
  std::istringstream text(output);
  for (std::string line; std::getline(text, line);) {
    while (!line.empty() && line.back() == ' ') line.pop_back();  // isotprecv ends each byte with a space
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

std::size_t byte_count(const std::string& hex_line) {
  std::istringstream in(hex_line);
  std::size_t count = 0;
  for (std::string byte; in >> byte;) ++count;
  return count;
}

TEST(KernelIsoTp, IsotpsendAndIsotprecv_GetEveryReplyIncludingLongProfiles) {
  LDOEM_REQUIRE_KERNEL_ISOTP();
  TempDir dir;
  auto daemon = ChildProcess::start(LDOEM_EMUD_PATH,
                                    {"--scene", std::string(LDOEM_SOURCE_DIR) + "/scenes/minimal.yaml", "--can", "can:vcan0",
                                     "--no-flash", "--virtual-time", "--timeout", "120"},
                                    dir.path("daemon"));
  ASSERT_TRUE(daemon && daemon->wait_for_line("ready", false, std::chrono::seconds(20))) << daemon->stderr_text();
  // The kernel receiver: listens on 0x6C1, sends its flow control on 0x6C0, prints each message.
  // stdbuf: isotprecv prints with stdio, which would hold the lines until it exits.
  auto receiver = ChildProcess::start("/usr/bin/stdbuf", {"-oL", "/usr/bin/isotprecv", "-s", "6C0", "-d", "6C1", "-l", "vcan0"},
                                      dir.path("recv"));
  ASSERT_TRUE(receiver.has_value());
  // isotprecv says nothing when its socket is bound: give it a moment (UML is slow to start one).
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const std::vector<std::pair<std::string, std::string>> requests{
      {"01 02", "81 02 00 00 00 01"},          // GET_STATUS: IDLE
      {"04 03 00 00", "84 03 00 00 00 02"},    // TRANS_ROTATE (spin-up in virtual time)
      {"04 04", "84 04 00 00 00 03 00 00"},    // TRANS_MEASURE: OK
      {"03 01 00 01 39 FF", ""},               // one 0x39FF profile (sizes below)
      {"03 01 00 01 3D FF", ""},               // one 0x3DFF profile
  };
  std::size_t expected_lines = 0;
  for (const auto& [request, reply] : requests) {
    const std::string input = dir.write("request.hex", request + "\n");
    auto sender = ChildProcess::start("/bin/sh", {"-c", "/usr/bin/isotpsend -s 6C0 -d 6C1 vcan0 < " + input},
                                      dir.path("send"));
    ASSERT_TRUE(sender.has_value());
    ASSERT_EQ(sender->wait(std::chrono::seconds(10)), std::optional<int>(0)) << sender->stderr_text();
    ++expected_lines;
    for (int i = 0; i < 200 && received_lines(*receiver).size() < expected_lines; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    const auto lines = received_lines(*receiver);
    ASSERT_EQ(lines.size(), expected_lines) << "no reply to " << request << "; daemon: " << daemon->stderr_text();
    if (!reply.empty()) {
      EXPECT_EQ(lines.back(), reply) << request;
    }
  }
  const auto lines = received_lines(*receiver);
  // D4's table: sector 0 measures 1080 points (225 deg + 0.25 deg .. 135 deg), sector 1 is a
  // block of 0 points. Spec 3.5: 12 + 2 x 14 + 1080 x 2 (or x 4 with ECHO) + 4.
  EXPECT_EQ(byte_count(lines[3]), 2204u);
  EXPECT_EQ(lines[3].substr(0, 11), "83 01 39 FF");
  EXPECT_EQ(byte_count(lines[4]), 4364u);
  EXPECT_EQ(lines[4].substr(0, 11), "83 01 3D FF");
  receiver->stop();
  daemon->stop();
}

TEST(KernelIsoTp, ScanThroughTheKernelsIsoTp_GivesTheUserSpaceBytes) {
  LDOEM_REQUIRE_KERNEL_ISOTP();
  TempDir dir;
  const ScanRun user_space = scan_corridor(dir, "user-space", Route::can);
  const ScanRun kernel = scan_corridor(dir, "kernel", Route::kernel_isotp);
  ASSERT_EQ(user_space.exit_status, 0) << user_space.failure;
  ASSERT_EQ(kernel.exit_status, 0) << kernel.failure;
  expect_same_bytes(user_space, kernel, "can:vcan0 (user-space ISO-TP) vs can:isotp:vcan0 (kernel)");
}

}  // namespace
}  // namespace ldoem::e2e
