// ldoem-latency: how fast ldoem-emud answers and streams, as a host sees it (scripts/bench-latency.sh).
//
//   ldoem-latency (--tcp HOST:PORT | --can IF) [--requests N] [--profiles SECONDS] [--format HEX]
//                 [--cadence SECONDS]
//
// --requests N: N GET_STATUS round trips, one at a time; prints the median and p99 in us.
// --profiles S: TRANS_ROTATE 0 (the flash speed), TRANS_MEASURE, GET_PROFILE 0000 FORMAT, then
//   counts the profile telegrams that arrive in S wall seconds (D10: the daemon skips profiles
//   the host is too slow for, so this is what the host gets, not what the LD measures).
// --cadence S: the same stream for S wall seconds of a daemon at --time-scale 1; each profile's
//   arrival lag behind its own TSTART (wall since the first arrival minus device time since
//   the first TSTART), less the smallest lag: how late the host got each revolution beyond the
//   best case (scripts/bench-jitter.sh). Prints p50, p99 and max in ms.
// Output: key=value lines, one per measurement. Exit 0, 1 on a transport failure, 2 on usage.
#include <memory>
#include <iostream>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <poll.h>

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/numbers.hpp"
#include "ldoem/endpoints/isotp_channel.hpp"
#include "ldoem/io/can_socket.hpp"
#include "ldoem/io/tcp.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "ldoem/protocol/text.hpp"

namespace {

using namespace std::chrono_literals;
using ldoem::protocol::Bytes;
using Clock = std::chrono::steady_clock;

bool wait_readable(int fd, std::chrono::milliseconds limit) {
  pollfd descriptor{fd, POLLIN, 0};
  return ::poll(&descriptor, 1, static_cast<int>(limit.count())) > 0;
}

// One host link: send a telegram payload, receive the next telegram payload.
class Link {
 public:
  virtual ~Link() = default;
  virtual bool send(const Bytes& payload) = 0;
  virtual std::optional<Bytes> next(std::chrono::milliseconds limit) = 0;
  // Wire bytes of the telegrams received so far (TCP frames, or CAN data bytes).
  std::uint64_t wire_bytes = 0;
};

class TcpLink final : public Link {
 public:
  explicit TcpLink(ldoem::io::TcpConnection connection) : connection_(std::move(connection)) {}
  bool send(const Bytes& payload) override {
    const Bytes frame = ldoem::protocol::encode_tcp_frame(payload);
    std::size_t sent = 0;
    while (sent < frame.size()) {
      auto count = connection_.send(ldoem::protocol::ByteView(frame).subspan(sent));
      if (!count) return false;
      sent += *count;
    }
    return true;
  }
  std::optional<Bytes> next(std::chrono::milliseconds limit) override {
    const auto deadline = Clock::now() + limit;
    for (;;) {
      if (!pending_.empty()) {
        Bytes payload = std::move(pending_.front());
        pending_.erase(pending_.begin());
        wire_bytes += ldoem::protocol::tcp_frame_size(payload.size());
        return payload;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (left <= 0ms || !wait_readable(connection_.fd(), left)) return std::nullopt;
      auto received = connection_.receive();
      if (!received || (received->bytes.empty() && received->peer_closed)) return std::nullopt;
      for (auto& event : deframer_.feed(received->bytes)) {
        if (auto* telegram = std::get_if<ldoem::protocol::Telegram>(&event)) pending_.push_back(std::move(telegram->payload));
      }
    }
  }

 private:
  ldoem::io::TcpConnection connection_;
  ldoem::protocol::TcpDeframer deframer_;
  std::vector<Bytes> pending_;
};

// ISO-TP over CAN_RAW with the project's own channel, identifiers swapped (D1 defaults).
class CanLink final : public Link {
 public:
  explicit CanLink(ldoem::io::CanRawSocket socket)
      : socket_(std::move(socket)), channel_(ldoem::endpoints::IsoTpChannelConfig{ldoem::endpoints::CanIdPair{0x6C1, 0x6C0}}) {}
  bool send(const Bytes& payload) override { return transmit(channel_.send(elapsed(), payload).frames); }
  std::optional<Bytes> next(std::chrono::milliseconds limit) override {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      if (!pending_.empty()) {  // telegrams completed by an earlier batch of frames
        Bytes payload = std::move(pending_.front());
        pending_.erase(pending_.begin());
        return payload;
      }
      if (!wait_readable(socket_.fd(), 5ms)) {
        transmit(channel_.poll(elapsed()).frames);
        continue;
      }
      for (;;) {
        auto frame = socket_.receive();
        if (!frame) return std::nullopt;
        if (!frame->has_value()) break;
        wire_bytes += (*frame)->length;
        auto out = channel_.on_frame(elapsed(), **frame);
        transmit(out.frames);
        for (auto& telegram : out.telegrams) pending_.push_back(std::move(telegram));
      }
    }
    return std::nullopt;
  }

 private:
  ldoem::base::SimTime elapsed() const { return Clock::now() - start_; }
  bool transmit(const std::vector<ldoem::protocol::CanFrame>& frames) {
    for (const auto& frame : frames) {
      for (;;) {
        auto sent = socket_.send(frame);
        if (!sent) return false;
        if (*sent == ldoem::io::SendOutcome::sent) break;
        pollfd descriptor{socket_.fd(), POLLOUT, 0};
        ::poll(&descriptor, 1, 10);
      }
    }
    return true;
  }
  ldoem::io::CanRawSocket socket_;
  ldoem::endpoints::IsoTpChannel channel_;
  Clock::time_point start_ = Clock::now();
  std::vector<Bytes> pending_;
};

Bytes telegram(std::string_view text) { return ldoem::protocol::parse_telegram(text).value(); }

std::uint16_t service_of(const Bytes& payload) {
  return payload.size() >= 2 ? static_cast<std::uint16_t>(payload[0] << 8 | payload[1]) : 0;
}

// The reply to `request`, skipping profile telegrams (0x8301) that may still arrive.
std::optional<Bytes> exchange(Link& link, const Bytes& request, std::chrono::milliseconds limit = 20s) {
  if (!link.send(request)) return std::nullopt;
  const auto deadline = Clock::now() + limit;
  while (Clock::now() < deadline) {
    auto payload = link.next(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()));
    if (!payload) return std::nullopt;
    if (service_of(*payload) != 0x8301) return payload;
  }
  return std::nullopt;
}

int measure_requests(Link& link, int count, const std::string& transport) {
  const Bytes request = telegram("GET_STATUS");
  std::vector<double> microseconds;
  microseconds.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const auto sent = Clock::now();
    const auto reply = exchange(link, request, 5s);
    if (!reply || service_of(*reply) != 0x8102) {
      std::fprintf(stderr, "ldoem-latency: GET_STATUS %d: no reply\n", i);
      return 1;
    }
    microseconds.push_back(std::chrono::duration<double, std::micro>(Clock::now() - sent).count());
  }
  std::sort(microseconds.begin(), microseconds.end());
  const auto at = [&](double fraction) {
    return microseconds[std::min(microseconds.size() - 1, static_cast<std::size_t>(fraction * microseconds.size()))];
  };
  std::printf("transport=%s measure=get_status requests=%d median_us=%.1f p99_us=%.1f max_us=%.1f\n",
              transport.c_str(), count, at(0.5), at(0.99), microseconds.back());
  return 0;
}

int measure_profiles(Link& link, double seconds, const std::string& format, const std::string& transport) {
  for (const char* step : {"TRANS_ROTATE 0000", "TRANS_MEASURE"}) {
    if (!exchange(link, telegram(step), 30s)) {
      std::fprintf(stderr, "ldoem-latency: %s: no reply\n", step);
      return 1;
    }
  }
  if (!link.send(telegram("GET_PROFILE 0000 " + format))) return 1;
  std::uint64_t profiles = 0;
  std::optional<Clock::time_point> first;
  Clock::time_point last{};
  std::uint64_t bytes_at_first = 0;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds) + 5s;  // waits for the first
  while (Clock::now() < end) {
    auto payload = link.next(200ms);
    if (!payload) continue;
    if (service_of(*payload) != 0x8301) continue;  // the GET_PROFILE reply itself is the first profile
    last = Clock::now();
    if (!first) {
      first = last;
      bytes_at_first = link.wire_bytes;
      continue;  // the clock starts at the first profile
    }
    ++profiles;
    if (last - *first >= std::chrono::duration<double>(seconds)) break;
  }
  exchange(link, telegram("CANCEL_PROFILE"), 10s);
  if (!first || profiles == 0) {
    std::fprintf(stderr, "ldoem-latency: no profiles\n");
    return 1;
  }
  const double span_s = std::chrono::duration<double>(last - *first).count();
  std::printf("transport=%s measure=profiles format=%s seconds=%.2f profiles=%llu profiles_per_s=%.1f bytes_per_s=%.0f\n",
              transport.c_str(), format.c_str(), span_s, static_cast<unsigned long long>(profiles), profiles / span_s,
              static_cast<double>(link.wire_bytes - bytes_at_first) / span_s);
  return 0;
}

int measure_cadence(Link& link, double seconds, const std::string& transport) {
  for (const char* step : {"TRANS_ROTATE 0000", "TRANS_MEASURE"}) {
    if (!exchange(link, telegram(step), 30s)) {
      std::fprintf(stderr, "ldoem-latency: %s: no reply\n", step);
      return 1;
    }
  }
  if (!link.send(telegram("GET_PROFILE 0000 39ff"))) return 1;
  std::vector<double> lags;
  std::optional<std::pair<Clock::time_point, std::uint16_t>> first;
  std::uint16_t last_tstart = 0;
  double device_ms = 0;  // TSTART since the first profile, unwrapped (16-bit ms, spec 2.3)
  std::uint64_t skipped = 0;
  std::uint16_t last_count = 0;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds) + 5s;
  while (Clock::now() < end) {
    auto payload = link.next(200ms);
    if (!payload || service_of(*payload) != 0x8301) continue;
    const auto at = Clock::now();
    auto profile = ldoem::protocol::decode_profile(*payload);
    if (!profile || profile->sectors.empty()) continue;
    const std::uint16_t tstart = profile->sectors.front().t_start_ms;
    if (!first) {
      first = {at, tstart};
    } else {
      device_ms += static_cast<std::uint16_t>(tstart - last_tstart);
      skipped += static_cast<std::uint16_t>(profile->profile_count - last_count) - 1u;
    }
    last_tstart = tstart;
    last_count = profile->profile_count;
    lags.push_back(std::chrono::duration<double, std::milli>(at - first->first).count() - device_ms);
    if (at - first->first >= std::chrono::duration<double>(seconds)) break;
  }
  exchange(link, telegram("CANCEL_PROFILE"), 10s);
  if (lags.size() < 2) {
    std::fprintf(stderr, "ldoem-latency: no profiles\n");
    return 1;
  }
  const double best = *std::min_element(lags.begin(), lags.end());
  for (double& lag : lags) lag -= best;
  std::sort(lags.begin(), lags.end());
  const auto at = [&](double fraction) {
    return lags[std::min(lags.size() - 1, static_cast<std::size_t>(fraction * lags.size()))];
  };
  std::printf("transport=%s measure=cadence profiles=%zu skipped=%llu lag_p50_ms=%.2f lag_p99_ms=%.2f lag_max_ms=%.2f\n",
              transport.c_str(), lags.size(), static_cast<unsigned long long>(skipped), at(0.5), at(0.99), lags.back());
  return 0;
}

int usage(const std::string& reason) {
  std::cerr << ldoem::base::usage_error_line("ldoem-latency", reason);
  return 2;
}

std::string usage_text() {
  return "usage: ldoem-latency (--tcp HOST:PORT | --can IF) [--requests N] [--profiles SECONDS]\n"
         "                     [--format HEX] [--cadence SECONDS]\n"
         "How fast ldoem-emud answers and streams, as a host sees it (scripts/bench-latency.sh).\n"
         "\n"
         "Options:\n"
         "  --tcp HOST:PORT       the daemon's TCP endpoint\n"
         "  --can IF              its CAN interface (ids 6C0:6C1)\n"
         "  --requests N          N GET_STATUS round trips; prints the median and p99 in us\n"
         "  --profiles SECONDS    profile telegrams that arrive in SECONDS wall seconds\n"
         "  --format HEX          GET_PROFILE's format mask [39ff]\n"
         "  --cadence SECONDS     each profile's lag behind its TSTART; p50, p99, max in ms\n"
         "  --help, -h            the most used options\n"
         "  --help-all            this text\n"
         "  --version             print the name and version\n"
         "  --completion bash     print a bash completion\n"
         "\n"
         "Output: key=value lines, one per measurement. Exit 0, 1 on a transport failure, 2 on usage.\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string tcp, can, format = "39ff";
  int requests = 0;
  double profile_seconds = 0;
  double cadence_seconds = 0;
  ldoem::base::CommandLine command_line("ldoem-latency");
  CLI::App& app = command_line.app();
  app.add_option("--tcp", tcp);
  app.add_option("--can", can);
  app.add_option("--format", format);
  ldoem::base::take_text(app, "--requests", [&requests](const std::string& value) -> std::optional<std::string> {
    const auto count = ldoem::base::parse_integer<int>(value);
    if (!count || *count < 0) return "`" + value + "` is not a count";
    requests = *count;
    return std::nullopt;
  });
  for (auto [name, slot] : {std::pair{"--profiles", &profile_seconds}, {"--cadence", &cadence_seconds}}) {
    ldoem::base::take_text(app, name, [slot = slot](const std::string& value) -> std::optional<std::string> {
      const auto seconds = ldoem::base::parse_double(value);
      if (!seconds || *seconds < 0) return "`" + value + "` is not a number of seconds";
      *slot = *seconds;
      return std::nullopt;
    });
  }
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  if (auto problem = command_line.parse(args)) return usage(*problem);
  if (command_line.help_all_requested()) return std::cout << usage_text(), 0;
  if (command_line.help_requested()) {
    std::cout << ldoem::base::brief_help("ldoem-latency", usage_text(), "Measure ldoem-emud's reply latency and profile rate.",
                                         {"--tcp", "--can", "--requests", "--profiles", "--cadence", "--help", "--version"});
    return 0;
  }
  if (command_line.version_requested()) return std::cout << ldoem::base::version_line("ldoem-latency"), 0;
  if (command_line.completion_requested()) return std::cout << command_line.completion_script(), 0;
  if (tcp.empty() == can.empty()) return usage("give one of --tcp HOST:PORT and --can IF");
  std::unique_ptr<Link> link;
  if (!tcp.empty()) {
    const auto colon = tcp.rfind(':');
    if (colon == std::string::npos) return usage("--tcp: `" + tcp + "` is not HOST:PORT");
    auto connection = ldoem::io::TcpConnection::connect(tcp.substr(0, colon),
                                                        static_cast<std::uint16_t>(std::atoi(tcp.c_str() + colon + 1)));
    if (!connection) {
      std::fprintf(stderr, "ldoem-latency: %s\n", connection.error().message().c_str());
      return 1;
    }
    link = std::make_unique<TcpLink>(std::move(*connection));
  } else {
    const std::vector<ldoem::io::CanIdFilter> filters{ldoem::io::exact_standard_id(0x6C1)};
    auto socket = ldoem::io::CanRawSocket::open(can, filters);
    if (!socket) {
      std::fprintf(stderr, "ldoem-latency: %s\n", socket.error().message().c_str());
      return 1;
    }
    link = std::make_unique<CanLink>(std::move(*socket));
  }
  const std::string transport = tcp.empty() ? "can" : "tcp";
  if (requests > 0 && measure_requests(*link, requests, transport) != 0) return 1;
  if (profile_seconds > 0 && measure_profiles(*link, profile_seconds, format, transport) != 0) return 1;
  if (cadence_seconds > 0 && measure_cadence(*link, cadence_seconds, transport) != 0) return 1;
  return 0;
}
