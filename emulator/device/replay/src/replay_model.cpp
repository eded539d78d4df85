#include "ldoem/replay/replay_model.hpp"

#include <algorithm>
#include <sstream>

#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/service_codes.hpp"
#include "ldoem/protocol/text.hpp"

namespace ldoem::replay {

using control::Actions;
using protocol::ConnectionId;

namespace {

// A recorded 0x8301 is a profile telegram: logged at debug and counted (--count-profiles), as the
// control unit's are.
bool is_profile_payload(protocol::ByteView payload) {
  return payload.size() >= 2 &&
         protocol::read_word_be(payload, 0) == protocol::response_code(protocol::Service::get_profile);
}

}  // namespace

ReplayModel::ReplayModel(ReplayDevice device, Warn warn, std::ostream& report)
    : device_(std::move(device)), warn_(std::move(warn)), report_(report) {}

Actions ReplayModel::handle_request(SimTime now, ConnectionId from, protocol::ByteView payload,
                                    const control::TransportQuery& transport) {
  ReplayAnswer answer = device_.on_request(now, payload);
  if (answer.diagnostic && warn_) warn_(protocol::to_string(from) + ": " + *answer.diagnostic);
  auto& queue = outgoing_[from];
  for (auto& telegram : answer.telegrams) queue.push_back(std::move(telegram));
  return pump(now, from, transport);
}

Actions ReplayModel::on_framing_error(SimTime now, ConnectionId from, const protocol::FramingError& error) {
  // D2: a broken frame is answered reason 5 (or 2 for a serial length mismatch), as the device
  // would. It leaves after what is already due for the connection.
  const protocol::ServiceFailure failure{error.request_code, protocol::failure_reason_for_framing(error.detail)};
  outgoing_[from].push_back({now, protocol::encode_response(failure)});
  struct NeverBusy final : control::TransportQuery {
    bool busy(ConnectionId) const override { return false; }
  };
  // No busy question here (the daemon asks it on the next wake-up): send what is due now.
  return pump(now, from, NeverBusy{});
}

Actions ReplayModel::on_connection_closed(SimTime, ConnectionId connection) {
  Actions out;
  outgoing_.erase(connection);
  if (const auto wake = wakeups_.find(connection); wake != wakeups_.end()) {
    out.cancelled_timers.push_back(wake->second);
    woken_.erase(wake->second);
    wakeups_.erase(wake);
  }
  return out;
}

Actions ReplayModel::on_timer(SimTime now, control::TimerId timer, const control::TransportQuery& transport) {
  const auto found = woken_.find(timer);
  if (found == woken_.end()) return {};
  const ConnectionId connection = found->second;
  woken_.erase(found);
  wakeups_.erase(connection);
  return pump(now, connection, transport);
}

Actions ReplayModel::pump(SimTime now, ConnectionId connection, const control::TransportQuery& transport) {
  Actions out;
  const auto found = outgoing_.find(connection);
  if (found == outgoing_.end()) return out;
  auto& queue = found->second;
  // One telegram per event: whether the endpoint is busy is known only after it was sent.
  bool sent = false;
  if (!queue.empty() && queue.front().at <= now && !transport.busy(connection)) {
    const bool profile = is_profile_payload(queue.front().payload);
    if (profile) ++diagnostics_.profiles_sent;
    out.telegrams.push_back({connection, std::move(queue.front().payload),
                             profile ? control::TelegramKind::profile : control::TelegramKind::reply});
    queue.pop_front();
    sent = true;
  }
  if (queue.empty() || wakeups_.contains(connection)) return out;
  // Not due yet, or the endpoint is still sending the previous telegram: look again then.
  const SimTime next = queue.front().at > now ? queue.front().at : (sent ? now : now + std::chrono::milliseconds(1));
  const control::TimerId id{next_timer_++};
  wakeups_[connection] = id;
  woken_[id] = connection;
  out.timers.push_back({next, id});
  return out;
}

void ReplayModel::report_at_exit() const {
  const ReplayCounters& counters = device_.counters();
  report_ << "ldoem-emud: replay: requests=" << counters.requests << " in_order=" << counters.in_order
          << " out_of_order=" << counters.out_of_order << " unexpected=" << counters.unexpected << '\n';
}

base::Expected<std::unique_ptr<ReplayModel>, std::string> load_replay_model(const ReplaySource& source,
                                                                            ReplayModel::Warn warn,
                                                                            std::ostream& report) {
  const std::string name = source.capture.string();
  capture::ConversationConfig config;
  config.tcp_port = source.capture_tcp_port;  // unset: detected from the frames (docs/replay.md)
  if (source.can_ids) {
    config.request_can_id = source.can_ids->first;
    config.response_can_id = source.can_ids->second;
  }
  auto loaded = capture::read_capture_conversation(source.capture, config);
  if (!loaded) return base::Unexpected(loaded.error());
  if (!loaded->warning.empty()) report << "ldoem-emud: warning: " << loaded->warning << '\n';
  const auto& telegrams = loaded->conversation.telegrams;
  const auto transport = source.transport ? source.transport : capture::busiest_transport(telegrams);
  if (!transport) return base::Unexpected(name + ": no LD-OEM telegram in it");
  auto exchanges = capture::exchanges_of(telegrams, *transport);
  if (exchanges.empty()) {
    return base::Unexpected(name + ": no request on " + std::string(protocol::transport_name(*transport)));
  }
  const auto& counters = loaded->conversation.counters;
  std::ostringstream line;
  line << "ldoem-emud: replay: " << name << ": " << exchanges.size() << " exchanges ("
       << protocol::transport_name(*transport);
  if (*transport == protocol::Transport::tcp) {
    line << ", device port " << loaded->conversation.tcp_port
         << (loaded->conversation.tcp_port_detected ? " (detected)" : "");
  }
  line << "); " << counters.packets << " packets, " << counters.framing_errors << " framing errors, "
       << counters.tcp_gaps << " TCP gaps, " << counters.ignored_packets << " ignored\n";
  report << line.str() << std::flush;
  return std::make_unique<ReplayModel>(ReplayDevice(std::move(exchanges)), std::move(warn), report);
}

}  // namespace ldoem::replay
