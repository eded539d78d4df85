// libFuzzer target: the control unit (emulator/device/control) driven by random request sequences.
//
// Input: records. Each starts with an op byte: bits 0..1 choose the event (0: a request built
// from a known service code and parameter bytes from the input; 1: simulated time advances by
// (bits 2..7)^2 * 10 ms and every due timer fires in order; 2: a raw payload of any bytes; 3: a
// connection closes), bits 2..3 pick one of four connections (TCP, TCP, serial, CAN).
//
// Checked, besides ASan/UBSan:
//   - each request gets exactly its one reply, to the connection that asked and carrying its
//     own service code (response bit set) or SERVICE_FAILURE, or its documented silence: none
//     for a GET_PROFILE that started a stream, none for a TRANS_ROTATE that waits for the head;
//   - the state table: a request answered SERVICE_FAILURE leaves the device state unchanged,
//     only TRANS_* and DO_RESET change the mode, TRANS_MEASURE never enters MEASURE from IDLE;
//   - a timer sends reply-kind telegrams only for a held TRANS_ROTATE.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <span>

#include "ldoem/control/control_unit.hpp"
#include "ldoem/protocol/service_codes.hpp"

namespace {

namespace c = ldoem::control;
namespace p = ldoem::protocol;
using ldoem::base::SimTime;

class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return offset_ >= size_; }
  std::uint8_t byte() { return offset_ < size_ ? data_[offset_++] : 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

class SteadyHead final : public c::HeadModel {
 public:
  SimTime time_to_reach(double, double) const override { return std::chrono::milliseconds(500); }
};

class FlatSource final : public c::MeasurementSource {
 public:
  void measure(const c::RevolutionQuery&, std::span<const c::BeamQuery> beams,
               std::span<c::BeamReturn> returns) override {
    for (std::size_t i = 0; i < beams.size(); ++i) returns[i] = c::BeamReturn{512, 100};
  }
};

class NeverBusy final : public c::TransportQuery {
 public:
  bool busy(c::ConnectionId) const override { return false; }
};

constexpr std::uint16_t kServices[] = {0x0101, 0x0102, 0x0104, 0x0105, 0x0106, 0x0201, 0x0202, 0x0203, 0x0204,
                                       0x0205, 0x0209, 0x020A, 0x020B, 0x0301, 0x0302, 0x0401, 0x0402, 0x0403,
                                       0x0404, 0x0601, 0x0701, 0x0801, 0x1234};

const c::ConnectionId kConnections[] = {{p::Transport::tcp, 1},
                                        {p::Transport::tcp, 2},
                                        {p::Transport::serial, 1},
                                        {p::Transport::can, 1}};

std::uint16_t service_of(p::ByteView payload) {
  return payload.size() >= 2 ? static_cast<std::uint16_t>(payload[0] << 8 | payload[1]) : 0;
}

void check(bool condition) {
  if (!condition) std::abort();
}

void check_request(const c::ControlUnit& unit, const c::DeviceState& before, c::ConnectionId from,
                   p::ByteView payload, const c::Actions& actions) {
  const std::uint16_t service = service_of(payload);
  int replies = 0;
  bool failed = false;
  for (const c::OutgoingTelegram& telegram : actions.telegrams) {
    if (telegram.kind != c::TelegramKind::reply) continue;
    check(telegram.to == from);
    const std::uint16_t code = service_of(telegram.payload);
    failed = code == p::code_of(p::Service::service_failure);
    check(failed || code == p::response_code(service));
    ++replies;
  }
  const c::DeviceState& after = unit.state();
  const bool profile_started = service == p::code_of(p::Service::get_profile) && after.streams.count(from) != 0;
  const bool rotate_held = service == p::code_of(p::Service::trans_rotate) && after.spin_up &&
                           after.spin_up->reply_to == from;
  if (replies == 0) {
    check(profile_started || rotate_held);
  } else {
    check(replies == 1);
  }
  if (failed) {
    check(after == before);
  }
  const bool changes_mode = service == p::code_of(p::Service::trans_idle) ||
                            service == p::code_of(p::Service::trans_rotate) ||
                            service == p::code_of(p::Service::trans_measure) ||
                            service == p::code_of(p::Service::do_reset);
  if (!changes_mode) check(after.mode == before.mode);
  if (service == p::code_of(p::Service::trans_measure) && before.mode == c::DeviceMode::idle) {
    check(after.mode != c::DeviceMode::measure);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Input input(data, size);
  SteadyHead head;
  FlatSource source;
  NeverBusy transport;
  c::ControlUnit unit(c::ControlUnit::Setup{}, head, source);
  SimTime now{};
  std::multimap<std::pair<SimTime, std::uint64_t>, c::TimerId> timers;
  const auto keep_timers = [&](const c::Actions& actions) {
    for (const c::TimerRequest& timer : actions.timers) {
      check(timer.at >= now);
      timers.emplace(std::make_pair(timer.at, timer.id.value), timer.id);
    }
  };
  for (int events = 0; !input.empty() && events < 256; ++events) {
    const std::uint8_t op = input.byte();
    const c::ConnectionId from = kConnections[(op >> 2) & 3];
    switch (op & 3) {
      case 0:
      case 2: {
        p::Bytes payload;
        if ((op & 3) == 0) {
          const std::uint16_t service = kServices[input.byte() % std::size(kServices)];
          payload = {static_cast<std::uint8_t>(service >> 8), static_cast<std::uint8_t>(service)};
        }
        const std::size_t length = input.byte() % 48;
        for (std::size_t i = 0; i < length; ++i) payload.push_back(input.byte());
        const c::DeviceState before = unit.state();
        const c::Actions actions = unit.handle_request(now, from, payload, transport);
        check_request(unit, before, from, payload, actions);
        keep_timers(actions);
        break;
      }
      case 1: {
        const int step = op >> 2;
        const SimTime until = now + std::chrono::milliseconds(step * step * 10);
        while (!timers.empty() && timers.begin()->first.first <= until) {
          const auto [key, id] = *timers.begin();
          timers.erase(timers.begin());
          now = std::max(now, key.first);
          const bool held = unit.state().spin_up.has_value();
          const c::Actions actions = unit.on_timer(now, id, transport);
          for (const c::OutgoingTelegram& telegram : actions.telegrams) {
            check(telegram.kind != c::TelegramKind::reply || held);
          }
          keep_timers(actions);
        }
        now = until;
        break;
      }
      case 3: {
        const c::Actions actions = unit.on_connection_closed(now, from);
        for (const c::OutgoingTelegram& telegram : actions.telegrams) check(!(telegram.to == from));
        keep_timers(actions);
        break;
      }
    }
  }
  return 0;
}
