// A socket endpoint (TCP on loopback, serial on a pty) opened in a real event loop, with the test
// as its device: telegrams, framing errors and closed connections are recorded, simulated time
// stands at 0. Every wait is bounded by a wall-clock limit.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

#include "ldoem/endpoints/host_endpoint.hpp"

namespace ldoem::endpoints::test {

inline std::unique_ptr<io::EventLoop> make_loop() {
  auto created = io::EventLoop::create();
  return created ? std::move(*created) : nullptr;
}

struct EndpointHarness final : Scheduler, EndpointSink, LptSink {
  std::unique_ptr<io::EventLoop> loop = make_loop();
  std::ostringstream out;
  std::ostringstream log;
  Logger logger{log, LogLevel::info};
  Counters counters;
  std::uint64_t activity = 0;
  EndpointContext context{*loop, *this, *this, *this, logger, out, counters, activity};

  std::vector<std::pair<ConnectionId, protocol::Bytes>> telegrams;
  std::vector<std::pair<ConnectionId, protocol::FramingError>> framing_errors;
  std::vector<ConnectionId> closed;

  // Runs the loop until `done` or `limit` of wall time; returns done().
  bool run_until(const std::function<bool()>& done, std::chrono::milliseconds limit = std::chrono::seconds(5)) {
    const auto give_up = std::chrono::steady_clock::now() + limit;
    while (!done() && std::chrono::steady_clock::now() < give_up) {
      if (!loop->run_once(std::chrono::milliseconds(10))) return false;
    }
    return done();
  }
  void run_for(std::chrono::milliseconds duration) {
    run_until([] { return false; }, duration);
  }

  // Scheduler: simulated time stands still; the socket endpoints ask nothing of it.
  SimTime now() override { return SimTime::zero(); }
  SimTime at_wall_time(WallTime) override { return SimTime::zero(); }
  Key add(SimTime at, Action) override { return {at, 0}; }
  void cancel(const Key&) override {}
  // EndpointSink
  void on_telegram(ConnectionId from, protocol::Bytes payload) override { telegrams.emplace_back(from, std::move(payload)); }
  void on_framing_error(ConnectionId from, const protocol::FramingError& error) override {
    framing_errors.emplace_back(from, error);
  }
  void on_connection_closed(ConnectionId connection) override { closed.push_back(connection); }
  // LptSink
  void on_register_write(SimTime, std::uint8_t) override {}
  void set_initial_register(std::uint8_t) override {}
  void on_line_change(SimTime, std::uint8_t, bool) override {}
  std::uint64_t steps_seen() const override { return 0; }
};

}  // namespace ldoem::endpoints::test
