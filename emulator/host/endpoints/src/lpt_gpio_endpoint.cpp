#include "ldoem/endpoints/lpt_gpio_endpoint.hpp"

#include <iterator>
#include <utility>
#include <vector>

#include "ldoem/protocol/lpt.hpp"

namespace ldoem::endpoints {
namespace {

// Line names of the gpio-sim chip, in DATA0..2 order, and their register bits.
const std::vector<std::string> kLptLineNames{"DIR", "CLK", "MODE"};
constexpr std::uint8_t kLptLineBits[] = {protocol::kLptDirectionBit, protocol::kLptClockBit, protocol::kLptModeBit};

}  // namespace

std::optional<OpenFailure> LptGpioEndpoint::open(EndpointContext& context) {
  context_ = &context;
  auto reader = io::GpioLineReader::open(chip_, kLptLineNames);
  if (!reader) {
    return OpenFailure{true, reader.error().message()};
  }
  reader_.emplace(std::move(*reader));
  auto levels = reader_->levels();
  if (!levels) {
    return OpenFailure{true, levels.error().message()};
  }
  std::uint8_t initial = 0;
  for (std::size_t i = 0; i < levels->size() && i < std::size(kLptLineBits); ++i) {
    if ((*levels)[i] != 0) initial |= kLptLineBits[i];
  }
  context.lpt.set_initial_register(initial);  // the lines' levels before any edge (D8)
  for (const int fd : reader_->event_fds()) {
    if (auto failure = watch_readable(context, fd, [this](io::Readiness) { on_ready(); }, io::kFirstInRound)) {
      return failure;
    }
  }
  context.out << "lpt gpio " << reader_->chip_name() << '\n';
  return std::nullopt;
}

void LptGpioEndpoint::on_ready() {
  ++context_->activity;
  auto events = reader_->read_events();
  if (!events) {
    context_->logger.log(LogLevel::warn, events.error().message());
    return;
  }
  for (const io::GpioEdgeEvent& edge : *events) {
    if (edge.line_index >= std::size(kLptLineBits)) continue;
    // Kernel timestamps are CLOCK_MONOTONIC, the wall clock the simulated one runs on (D7).
    const SimTime at = context_->scheduler.at_wall_time(WallTime(std::chrono::duration_cast<WallTime::duration>(edge.timestamp)));
    const std::uint8_t bit = kLptLineBits[edge.line_index];
    const bool level = edge.edge == io::Edge::rising;
    if (fault_hook_ != nullptr && bit == protocol::kLptClockBit && step_lost(at, level)) continue;
    context_->lpt.on_line_change(at, bit, level);
  }
}

// D11 lpt_lose_steps, lpt_jam: the rising clock edge of a lost step and its falling edge never
// reach the plate, which keeps seeing the clock low.
bool LptGpioEndpoint::step_lost(SimTime at, bool level) {
  if (level) {
    clock_edge_lost_ = fault_hook_->loses_step(at);
    return clock_edge_lost_;
  }
  return std::exchange(clock_edge_lost_, false);
}

}  // namespace ldoem::endpoints
