#include "ldoem/endpoints/lpt_pty_endpoint.hpp"

#include "ldoem/endpoints/read_budget.hpp"
#include "ldoem/protocol/lpt.hpp"

namespace ldoem::endpoints {

std::optional<OpenFailure> LptPtyEndpoint::open(EndpointContext& context) {
  context_ = &context;
  auto pty = io::PseudoTerminal::open(link_path_);
  if (!pty) return OpenFailure{true, pty.error().message()};
  pty_.emplace(std::move(*pty));
  if (auto failure = watch_readable(context, pty_->fd(), [this](io::Readiness) { on_ready(); }, io::kFirstInRound)) {
    return failure;
  }
  context.out << "lpt " << pty_->peer_path() << ' ' << link_path_.string() << '\n';
  return std::nullopt;
}

void LptPtyEndpoint::on_ready() {
  ++context_->activity;
  take_pending_input();
}

void LptPtyEndpoint::take_pending_input() {
  if (!pty_) return;
  auto received = pty_->receive(kReadBudgetBytes);
  if (!received) {
    context_->logger.log(LogLevel::warn, received.error().message());
    return;
  }
  const SimTime at = context_->scheduler.now();  // D8: time-stamped on arrival
  for (const std::uint8_t value : received->bytes) {
    context_->lpt.on_register_write(at, fault_hook_ == nullptr ? value : as_the_plate_sees(at, value));
  }
}

// D11 lpt_lose_steps, lpt_jam: a rising clock edge the plate does not follow reaches it with the
// clock still low, and the next low byte is then no edge either: that step is lost, nothing else.
std::uint8_t LptPtyEndpoint::as_the_plate_sees(SimTime at, std::uint8_t value) {
  const bool rising = (value & protocol::kLptClockBit) != 0 && (seen_by_plate_ & protocol::kLptClockBit) == 0;
  if (rising && fault_hook_->loses_step(at)) value = static_cast<std::uint8_t>(value & ~protocol::kLptClockBit);
  seen_by_plate_ = value;
  return value;
}

}  // namespace ldoem::endpoints
