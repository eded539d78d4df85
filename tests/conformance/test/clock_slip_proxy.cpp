// A test double of a device whose clock slips: a TCP proxy in front of ldoem-emud that passes
// every telegram through unchanged except profiles, whose TSTART/TEND it moves by SLIP ms more
// with each profile of the connection (a clock running slow: SLIP ms lost per revolution). The
// conformance suite through it must fail its device-clock checks; straight to the daemon it
// passes (tests/conformance/clock-slip.sh).
//   clock_slip_proxy UPSTREAM_PORT SLIP_MS
// Listens on 127.0.0.1, port 0; prints "tcp 127.0.0.1:PORT" then "ready"; serves one host
// connection and exits when either side closes. Memory: the deframer's bound and one buffer.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace {

using namespace ldoem::protocol;

int fail(const std::string& what) {
  std::perror(("clock_slip_proxy: " + what).c_str());
  return 1;
}

bool write_all(int fd, ByteView bytes) {
  while (!bytes.empty()) {
    const ssize_t written = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (written <= 0) return false;
    bytes = bytes.subspan(static_cast<std::size_t>(written));
  }
  return true;
}

// The k-th profile (from 1) with its sectors' times k * slip ms early.
Bytes doctored(ByteView payload, std::uint64_t k, int slip_ms) {
  auto profile = decode_profile(payload);
  if (!profile) return Bytes(payload.begin(), payload.end());
  const auto shift = static_cast<std::uint16_t>(k * static_cast<std::uint64_t>(slip_ms));
  for (SectorBlock& sector : profile->sectors) {
    sector.t_start_ms = static_cast<std::uint16_t>(sector.t_start_ms - shift);
    sector.t_end_ms = static_cast<std::uint16_t>(sector.t_end_ms - shift);
  }
  return encode_profile(*profile);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: clock_slip_proxy UPSTREAM_PORT SLIP_MS\n");
    return 2;
  }
  const auto upstream_port = static_cast<std::uint16_t>(std::atoi(argv[1]));
  const int slip_ms = std::atoi(argv[2]);
  const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (listener < 0 || ::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(listener, 1) != 0) {
    return fail("listen");
  }
  socklen_t length = sizeof address;
  ::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length);
  std::printf("tcp 127.0.0.1:%u\nready\n", ntohs(address.sin_port));
  std::fflush(stdout);

  const int host = ::accept(listener, nullptr, nullptr);
  if (host < 0) return fail("accept");
  const int device = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  address.sin_port = htons(upstream_port);
  if (device < 0 || ::connect(device, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    return fail("connect upstream");
  }
  TcpDeframer from_device(kMaxTelegramPayload, TcpResync::rescan_dropped);
  std::uint64_t profiles = 0;
  std::uint8_t buffer[16384];
  pollfd fds[2] = {{host, POLLIN, 0}, {device, POLLIN, 0}};
  while (::poll(fds, 2, -1) > 0) {
    if (fds[0].revents != 0) {  // host -> device: unchanged
      const ssize_t got = ::recv(host, buffer, sizeof buffer, 0);
      if (got <= 0 || !write_all(device, ByteView(buffer, static_cast<std::size_t>(got)))) break;
    }
    if (fds[1].revents != 0) {  // device -> host: profiles doctored, everything else re-framed as is
      const ssize_t got = ::recv(device, buffer, sizeof buffer, 0);
      if (got <= 0) break;
      for (const DeframerEvent& event : from_device.feed(ByteView(buffer, static_cast<std::size_t>(got)))) {
        const auto* telegram = std::get_if<Telegram>(&event);
        if (telegram == nullptr) continue;  // a broken frame from the daemon: the suite sees it missing
        const bool profile = telegram->payload.size() >= 2 && telegram->payload[0] == 0x83 && telegram->payload[1] == 0x01;
        const Bytes payload = profile ? doctored(telegram->payload, ++profiles, slip_ms) : telegram->payload;
        if (!write_all(host, encode_tcp_frame(payload))) return 0;
      }
    }
  }
  return 0;
}
