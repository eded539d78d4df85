#include "ldoem/endpoints/lpt_pty_endpoint.hpp"

#include "ldoem/endpoints/read_budget.hpp"

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
    context_->lpt.on_register_write(at, value);
  }
}

}  // namespace ldoem::endpoints
