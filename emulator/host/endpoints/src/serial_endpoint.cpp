#include "ldoem/endpoints/serial_endpoint.hpp"

#include <variant>

#include "ldoem/endpoints/read_budget.hpp"
#include "ldoem/protocol/wire_corruption.hpp"

namespace ldoem::endpoints {

std::optional<OpenFailure> SerialHostEndpoint::open(EndpointContext& context) {
  context_ = &context;
  auto pty = io::PseudoTerminal::open(link_path_);
  if (!pty) return OpenFailure{true, pty.error().message()};
  pty_.emplace(std::move(*pty));
  if (auto failure = watch_readable(context, pty_->fd(), [this](io::Readiness r) { on_ready(r); })) return failure;
  context.out << "serial " << pty_->peer_path() << ' ' << link_path_.string() << '\n';
  return std::nullopt;
}

void SerialHostEndpoint::on_ready(io::Readiness readiness) {
  ++context_->activity;
  if (readiness.writable) {
    flush();
  }
  auto received = pty_->receive(kReadBudgetBytes);
  if (!received) {
    context_->logger.log(LogLevel::warn, received.error().message());
    return;
  }
  if (dark_) return;  // D11 power_cycle: the bytes are lost
  const ConnectionId connection{protocol::Transport::serial, 1};
  const auto events = deframer_.feed(received->bytes);
  if (!received->bytes.empty()) {
    if (inter_byte_timer_) context_->loop.cancel_timer(*inter_byte_timer_);
    inter_byte_timer_.reset();
    if (inter_byte_timeout_.count() > 0 && deframer_.in_frame()) {
      inter_byte_timer_ = context_->loop.add_timer_after(inter_byte_timeout_, [this] { on_inter_byte_timeout(); });
    }
  }
  for (const protocol::DeframerEvent& event : events) {
    if (const auto* telegram = std::get_if<protocol::Telegram>(&event)) {
      context_->sink.on_telegram(connection, telegram->payload);
    } else {
      context_->sink.on_framing_error(connection, std::get<protocol::FramingError>(event));
    }
  }
}

void SerialHostEndpoint::on_inter_byte_timeout() {
  inter_byte_timer_.reset();
  if (!deframer_.in_frame()) return;
  deframer_.reset();
  ++context_->activity;
  context_->logger.log(LogLevel::info, "serial#1: package incomplete after " + std::to_string(inter_byte_timeout_.count()) +
                                           " ms; dropped (spec 6)");
  context_->sink.on_framing_error(ConnectionId{protocol::Transport::serial, 1},
                                  protocol::FramingError{protocol::DecodeError::timeout, 0});
}

void SerialHostEndpoint::set_power(DevicePower power) {
  dark_ = power != DevicePower::on;
  if (!dark_ || context_ == nullptr) return;
  deframer_.reset();  // a package begun before the cut is not joined to one sent after it
  output_.clear();
  if (inter_byte_timer_) context_->loop.cancel_timer(*inter_byte_timer_);
  inter_byte_timer_.reset();
  if (pty_) (void)context_->loop.change_interest(pty_->fd(), io::Interest::readable);
}

void SerialHostEndpoint::send(ConnectionId to, protocol::ByteView payload) {
  if (dark_) return;
  // All packages of the reply in one write (D10).
  const bool pushed = fault_hook_ == nullptr ? output_.push(protocol::encode_serial_reply(payload))
                                             : output_.push(faulty_reply(to, payload));
  if (!pushed) {
    // Nobody reads the line: a real LD would lose the bytes on the wire as well.
    ++context_->counters.serial_overflows;
    output_.clear();
    return;
  }
  flush();
}

// D11 corrupt_checksum (the first package's CRC) and garbage (before the first package).
protocol::Bytes SerialHostEndpoint::faulty_reply(ConnectionId to, protocol::ByteView payload) {
  TelegramFaults faults = fault_hook_->on_outgoing_telegram(to, payload, context_->scheduler.now());
  std::vector<protocol::Bytes> packages = protocol::encode_serial_reply_packages(payload);
  if (faults.corrupt_checksum && !packages.empty()) protocol::corrupt_serial_crc(packages.front());
  protocol::Bytes reply = std::move(faults.garbage_before);
  for (const protocol::Bytes& package : packages) reply.insert(reply.end(), package.begin(), package.end());
  return reply;
}

void SerialHostEndpoint::flush() {
  if (!pty_) return;
  while (!output_.empty()) {
    auto sent = pty_->send(output_.front());
    note_echo_resets();
    if (!sent) {
      context_->logger.log(LogLevel::warn, sent.error().message());
      break;
    }
    if (*sent == 0) break;
    output_.consume(*sent);
  }
  (void)context_->loop.change_interest(pty_->fd(), output_.empty() ? io::Interest::readable
                                                                   : io::Interest::readable | io::Interest::writable);
}

// Said on the 1st, 10th, 100th, ... time: a host that switches ECHO on before every request
// must not fill the log.
void SerialHostEndpoint::note_echo_resets() {
  const std::uint64_t resets = pty_->echo_resets();
  if (resets == echo_resets_logged_) return;
  echo_resets_logged_ = resets;
  if (resets == next_echo_report_) {
    context_->logger.log(LogLevel::warn, "serial " + pty_->peer_path() +
                                             ": the host switched ECHO on; switched off again, it would send our "
                                             "replies back as requests (" + std::to_string(resets) + " times so far)");
    next_echo_report_ *= 10;
  }
}

}  // namespace ldoem::endpoints
