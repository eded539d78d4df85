// End to end without any device simulation: acquire() -> HubDevice -> ldoem-hub's Hub ->
// BEMH -> ScannerDevice -> Scanner -> TcpTransport -> a scripted LD behind a TCP server in
// this test (spec 4.1 framing). The cloud must be the one the direct path gives.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/hub/hub_client.hpp"
#include "ldoem/hub/hub_server.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "ldoem/scan/acquisition.hpp"
#include "scripted_ld.hpp"

namespace ldoem::scan {
namespace {

using std::chrono::milliseconds;

// Serves the scripted LD on 127.0.0.1:ephemeral, one connection at a time, until destroyed.
class ScriptedLdServer {
 public:
  explicit ScriptedLdServer(test::ScriptedLd& ld) : ld_(ld) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(listen_fd_, 4) != 0) {
      throw std::runtime_error("scripted LD: cannot listen");
    }
    socklen_t length = sizeof address;
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
    port_ = ntohs(address.sin_port);
    thread_ = std::thread([this] { serve(); });
  }
  ~ScriptedLdServer() {
    stop_.store(true);
    thread_.join();
    ::close(listen_fd_);
  }
  std::uint16_t port() const { return port_; }

 private:
  void serve() {
    while (!stop_.load()) {
      pollfd entry{listen_fd_, POLLIN, 0};
      if (::poll(&entry, 1, 50) <= 0) {
        continue;
      }
      const int fd = ::accept(listen_fd_, nullptr, nullptr);
      if (fd >= 0) {
        talk(fd);
        ::close(fd);
      }
    }
  }

  void talk(int fd) {
    protocol::TcpDeframer deframer;
    std::uint8_t buffer[8192];
    while (!stop_.load()) {
      pollfd entry{fd, POLLIN, 0};
      if (::poll(&entry, 1, 50) <= 0) {
        continue;
      }
      const ssize_t got = ::recv(fd, buffer, sizeof buffer, 0);
      if (got <= 0) {
        return;
      }
      for (auto& event : deframer.feed(protocol::ByteView(buffer, static_cast<std::size_t>(got)))) {
        if (const auto* telegram = std::get_if<protocol::Telegram>(&event)) {
          for (const protocol::Bytes& reply : ld_.handle(telegram->payload)) {
            const protocol::Bytes frame = protocol::encode_tcp_frame(reply);
            (void)::send(fd, frame.data(), frame.size(), MSG_NOSIGNAL);  // one send per reply (D10)
          }
        }
      }
    }
  }

  test::ScriptedLd& ld_;
  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

std::uint16_t ranges(std::uint32_t beam, std::int64_t tilt_half_steps) {
  return static_cast<std::uint16_t>(700 + 3 * beam + static_cast<std::int64_t>(5 * (tilt_half_steps + 100)));
}

TEST(ScanViaHub, ScriptedLdOverTcp_CloudMatchesTheScriptedRanges) {
  auto tilt_port = std::make_shared<test::TiltLptPort>();
  test::ScriptedLd ld(ranges, [tilt_port] { return tilt_port->position_half_steps(); });
  ScriptedLdServer server(ld);

  const std::uint16_t ld_port = server.port();
  driver::TransportFactory transport = [ld_port] {
    return driver::open_transport(driver::TcpEndpoint{"127.0.0.1", ld_port});
  };
  driver::LptFactory lpt = [tilt_port]() -> driver::Expected<std::unique_ptr<driver::LptPort>, driver::DriverError> {
    return std::unique_ptr<driver::LptPort>(std::make_unique<test::SharedTiltPort>(tilt_port));
  };
  std::vector<hub::DeviceSlot> slots;
  slots.push_back({"bench", std::make_unique<driver::ScannerDevice>("bench", transport, lpt,
                                                                 std::make_unique<test::VirtualSleeper>()),
                   milliseconds(5000)});
  hub::HubSettings settings;
  settings.listen = hub::ListenAddress{"127.0.0.1", 0};
  hub::Hub hub(settings, std::move(slots));
  ASSERT_TRUE(hub.listen());
  std::thread loop([&hub] { (void)hub.run(); });

  auto client = hub::HubClient::connect(hub::ListenAddress{"127.0.0.1", hub.port()}, milliseconds(5000));
  ASSERT_TRUE(client) << driver::describe(client.error());
  hub::HubDevice device(std::move(client.value()), "bench");

  AcquisitionPlan plan;
  plan.sectors = plan_sectors(10.0, 0.5, 10).value();  // 21 beams from -5 to +5 deg
  plan.layers = plan_layers(0.72, 0.09, true).value();  // 9 layers of 2 half-steps
  plan.step_rate_hz = 1000.0;
  auto scan = acquire(device, plan);
  hub.request_stop();
  loop.join();
  ASSERT_TRUE(scan) << describe(scan.error());

  ASSERT_EQ(plan.layers.layer_count, 9u);
  ASSERT_EQ(scan->cloud.size(), 9u * 21u);
  EXPECT_EQ(scan->device.identification.size(), driver::kIdentificationItems.size());
  for (std::uint32_t layer = 0; layer < 9; ++layer) {
    const std::int64_t half_steps = -8 + 2 * static_cast<std::int64_t>(layer);
    const double phi = half_steps * 0.045 * M_PI / 180.0;
    for (std::uint32_t beam = 0; beam < 21; ++beam) {
      const double range_m = ranges(beam, half_steps) / 256.0;
      const double theta = (-5.0 + 0.5 * beam) * M_PI / 180.0;
      // Organised as seen from the scanner: row 0 the highest layer, column 0 the leftmost beam.
      const cloud::PointRecord point = scan->cloud.record(std::size_t{8 - layer} * 21 + (20 - beam));
      EXPECT_NEAR(point.position.x_m, range_m * std::cos(theta) * std::cos(phi), 1e-5);
      EXPECT_NEAR(point.position.y_m, range_m * std::sin(theta), 1e-5);
      EXPECT_NEAR(point.position.z_m, range_m * std::cos(theta) * std::sin(phi), 1e-5);
    }
  }
  EXPECT_EQ(tilt_port->position_half_steps(), 0);
  EXPECT_EQ(ld.mode(), protocol::SensorMode::idle);
}

}  // namespace
}  // namespace ldoem::scan
