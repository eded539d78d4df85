// Fakes and a virtual-time bench for the control unit tests: a head with a fixed spin-up, a
// measurement source whose ranges are derived from the beam angle, a transport whose busy set
// the test controls, and a timer queue that fires in (time, id) order like the daemon.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/control/control_unit.hpp"
#include "ldoem/control/flash_image.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/text.hpp"

namespace ldoem::control::test {

using namespace std::chrono_literals;
using protocol::Bytes;

inline constexpr ConnectionId kTcp1{protocol::Transport::tcp, 1};
inline constexpr ConnectionId kTcp2{protocol::Transport::tcp, 2};
inline constexpr ConnectionId kSerial1{protocol::Transport::serial, 1};
inline constexpr ConnectionId kCan1{protocol::Transport::can, 1};

// D7's default is "about 2 s" from 0 to 10 Hz; the fake takes exactly `duration` for any change
// and records the speeds it was asked about.
class FixedSpinUpHead final : public HeadModel {
 public:
  SimTime duration = 2s;
  mutable std::vector<std::pair<double, double>> asked;
  SimTime time_to_reach(double from_hz, double to_hz) const override {
    asked.emplace_back(from_hz, to_hz);
    return duration;
  }
};

// DISTANCE = 256 + angle (1 m plus one 1/256 m per tick), ECHO = low 16 bits of the
// revolution: every value says where it came from.
class AngleDerivedSource final : public MeasurementSource {
 public:
  struct Call {
    std::uint64_t revolution;
    std::vector<BeamQuery> beams;
    SimTime revolution_start{};
  };
  std::vector<Call> calls;
  void measure(const RevolutionQuery& query, std::span<const BeamQuery> beams, std::span<BeamReturn> returns) override {
    const std::uint64_t revolution = query.number;
    calls.push_back(Call{revolution, std::vector<BeamQuery>(beams.begin(), beams.end()), query.start});
    for (std::size_t i = 0; i < beams.size(); ++i) {
      returns[i] = BeamReturn{static_cast<std::uint16_t>(256 + beams[i].angle_ticks),
                              static_cast<std::uint16_t>(revolution & 0xFFFF)};
    }
  }
};

class FakeTransportQuery final : public TransportQuery {
 public:
  std::set<ConnectionId> busy_connections;
  bool busy(ConnectionId connection) const override { return busy_connections.count(connection) != 0; }
};

// One telegram as the bench saw it leave, with the simulated time it left at.
struct Sent {
  SimTime at;
  OutgoingTelegram telegram;
  std::string text() const { return protocol::format_telegram(telegram.payload); }
};

inline Bytes encode(const protocol::Request& request) { return protocol::encode_request(request); }

// Text form of a request or reply (text.hpp grammar) -> payload bytes.
inline Bytes telegram(std::string_view text) {
  auto bytes = protocol::parse_telegram(text);
  EXPECT_TRUE(bytes.has_value()) << "bad telegram text: " << text;
  return bytes ? *bytes : Bytes{};
}

// Drives one ControlUnit in virtual time. Timers are kept like the daemon keeps them and fire
// in (time, id) order when time advances; every telegram is logged with its time.
class Bench {
 public:
  FixedSpinUpHead head;
  AngleDerivedSource source;
  FakeTransportQuery transport;
  ControlUnit unit;
  SimTime now{};
  std::vector<Sent> log;
  std::vector<Bytes> flash_writes;
  std::vector<TimerId> cancelled_timers;          // every Actions::cancelled_timers, in order
  std::vector<std::uint16_t> head_targets;        // every Actions::head_target_hz, in order
  std::vector<protocol::CanConfig> can_configs;   // every Actions::can_config, in order

  explicit Bench(ControlUnit::Setup setup = {}) : unit(std::move(setup), head, source) {}

  // Sends `payload` from `from` at the current time; returns what this request sent at once.
  std::vector<Sent> request(ConnectionId from, const Bytes& payload) {
    return apply(unit.handle_request(now, from, payload, transport));
  }
  std::vector<Sent> request(ConnectionId from, std::string_view text) { return request(from, telegram(text)); }
  std::vector<Sent> request(ConnectionId from, const protocol::Request& typed) { return request(from, encode(typed)); }

  // The connection closes now.
  std::vector<Sent> close(ConnectionId connection) { return apply(unit.on_connection_closed(now, connection)); }

  // The one reply a request must produce at once, as text ("" if none, failure if several).
  std::string reply_text(ConnectionId from, std::string_view text) {
    const auto sent = request(from, text);
    EXPECT_LE(sent.size(), 1u) << text;
    return sent.empty() ? std::string() : sent.front().text();
  }

  // Fires every timer due up to `until` in order, then sets now = until.
  void advance_to(SimTime until) {
    while (!timers_.empty() && timers_.begin()->first.first <= until) {
      const auto [key, id] = *timers_.begin();
      timers_.erase(timers_.begin());
      now = std::max(now, key.first);
      apply(unit.on_timer(now, id, transport));
    }
    now = std::max(now, until);
  }
  void advance_by(SimTime duration) { advance_to(now + duration); }

  // Like advance_to, but every due timer is delivered late, at `until` (a stalled daemon loop).
  void advance_late_to(SimTime until) {
    now = std::max(now, until);
    while (!timers_.empty() && timers_.begin()->first.first <= until) {
      const TimerId id = timers_.begin()->second;
      timers_.erase(timers_.begin());
      apply(unit.on_timer(now, id, transport));
    }
  }

  std::vector<Sent> sent_to(ConnectionId connection, TelegramKind kind) const {
    std::vector<Sent> result;
    for (const Sent& sent : log) {
      if (sent.telegram.to == connection && sent.telegram.kind == kind) result.push_back(sent);
    }
    return result;
  }
  std::vector<protocol::Profile> profiles_to(ConnectionId connection) const {
    std::vector<protocol::Profile> result;
    for (const Sent& sent : sent_to(connection, TelegramKind::profile)) {
      auto profile = protocol::decode_profile(sent.telegram.payload);
      EXPECT_TRUE(profile.has_value());
      if (profile) result.push_back(*profile);
    }
    return result;
  }
  std::size_t pending_timers() const { return timers_.size(); }
  // Actions from a call other than request/on_timer (fault injection): logged, timers armed.
  std::vector<Sent> deliver(Actions actions) { return apply(std::move(actions)); }

  // IDLE -> ROTATE (flash speed) -> MEASURE, leaving now at the end of the spin-up.
  void enter_measure(ConnectionId from = kTcp1) {
    request(from, "TRANS_ROTATE 0000");
    advance_by(head.duration);
    const auto sent = request(from, "TRANS_MEASURE");
    ASSERT_EQ(sent.size(), 1u);
    ASSERT_EQ(sent.front().text(), "TRANS_MEASURE reply 0000 0003 0000") << unit.dump(now);
  }

 private:
  std::vector<Sent> apply(Actions actions) {
    std::vector<Sent> sent;
    for (OutgoingTelegram& telegram : actions.telegrams) sent.push_back(Sent{now, std::move(telegram)});
    for (const TimerId cancelled : actions.cancelled_timers) {
      std::erase_if(timers_, [cancelled](const auto& entry) { return entry.second == cancelled; });
      cancelled_timers.push_back(cancelled);
    }
    for (const TimerRequest& timer : actions.timers) timers_.emplace(std::make_pair(timer.at, timer.id.value), timer.id);
    if (actions.head_target_hz) head_targets.push_back(*actions.head_target_hz);
    if (actions.can_config) can_configs.push_back(*actions.can_config);
    if (actions.flash_image) flash_writes.push_back(*actions.flash_image);
    log.insert(log.end(), sent.begin(), sent.end());
    return sent;
  }

  std::multimap<std::pair<SimTime, std::uint64_t>, TimerId> timers_;
};

}  // namespace ldoem::control::test
