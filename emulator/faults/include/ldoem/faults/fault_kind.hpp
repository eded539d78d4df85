// The D11 fault catalogue: every fault the emulator can inject, what it is (a device fault the
// LD-OEM would report, or a wire fault a cable, bus or network does to correct telegrams) and
// the transports it applies to. Names are the ones scenes and the control socket use.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "ldoem/protocol/transport.hpp"

namespace ldoem::faults {

enum class FaultKind : std::uint8_t {
  // Device faults (D11): status nibbles, modes, ranges.
  motor_stall, motor_overspeed, encoder_error, power_cycle, reset_spontaneous, blind, window_dirt,
  // Wire faults on any telegram transport.
  drop_reply, delay_reply, duplicate_reply, truncate_reply, corrupt_checksum, garbage,
  // TCP only.
  tcp_reset, tcp_stall, bandwidth,
  // CAN (ISO-TP) only.
  isotp_drop_cf, isotp_repeat_cf, isotp_bad_sn, isotp_fc_overflow, isotp_fc_wait, can_silence,
  // The pseudo-LPT stepper port only.
  lpt_lose_steps, lpt_jam,
};
inline constexpr std::size_t kFaultKindCount = 24;

enum class FaultClass : std::uint8_t { device, wire };

// Where a fault can act (protocol/transport.hpp). `any` in a fault entry means "every transport
// the kind applies to".
using protocol::Transport;
using protocol::TransportSet;

// Extra parameters a kind accepts (besides trigger, duration_s, count, transport, service).
enum class FaultParam : std::uint8_t {
  sector_range,  // from_deg, to_deg (blind)
  fraction,      // blind, window_dirt
  delay_s,       // delay_reply
  bytes_kept,    // truncate_reply
  bytes,         // garbage: how many bytes are inserted
  bytes_per_s,   // bandwidth
  off_s,         // power_cycle
};

struct FaultKindInfo {
  FaultKind kind;
  std::string_view name;
  FaultClass fault_class;
  TransportSet transports;  // the transports it applies to (empty: a device fault)
  // One-shot kinds act once when triggered (power_cycle, reset_spontaneous); others stay active
  // for their duration or count.
  bool one_shot;
};

const FaultKindInfo& info(FaultKind kind);
std::string_view fault_name(FaultKind kind);
std::optional<FaultKind> fault_kind_from_name(std::string_view name);
bool applies_to(FaultKind kind, Transport transport);
bool accepts(FaultKind kind, FaultParam param);
// "motor_stall, motor_overspeed, ..." for error messages.
std::string_view all_fault_names();

}  // namespace ldoem::faults
