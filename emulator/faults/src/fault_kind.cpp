#include "ldoem/faults/fault_kind.hpp"

#include <array>

namespace ldoem::faults {
namespace {

using enum FaultKind;
constexpr FaultClass kDevice = FaultClass::device;
constexpr FaultClass kWire = FaultClass::wire;

// Indexed by FaultKind. D11 lists the transports of each wire fault; device faults act on the
// device itself, whatever transport the host uses.
constexpr std::array<FaultKindInfo, kFaultKindCount> kCatalogue{{
    {motor_stall, "motor_stall", kDevice, false, false, false, false, false},
    {motor_overspeed, "motor_overspeed", kDevice, false, false, false, false, false},
    {encoder_error, "encoder_error", kDevice, false, false, false, false, false},
    {power_cycle, "power_cycle", kDevice, false, false, false, false, true},
    {reset_spontaneous, "reset_spontaneous", kDevice, false, false, false, false, true},
    {blind, "blind", kDevice, false, false, false, false, false},
    {window_dirt, "window_dirt", kDevice, false, false, false, false, false},
    {drop_reply, "drop_reply", kWire, true, true, true, false, false},
    {delay_reply, "delay_reply", kWire, true, true, true, false, false},
    {duplicate_reply, "duplicate_reply", kWire, true, true, true, false, false},
    {truncate_reply, "truncate_reply", kWire, true, true, true, false, false},
    // CAN frames carry their own CRC (D1): the checksum D11 corrupts is TCP's XOR or serial's CRC.
    {corrupt_checksum, "corrupt_checksum", kWire, true, true, false, false, false},
    {garbage, "garbage", kWire, true, true, true, false, false},
    {tcp_reset, "tcp_reset", kWire, true, false, false, false, false},
    {tcp_stall, "tcp_stall", kWire, true, false, false, false, false},
    {bandwidth, "bandwidth", kWire, true, false, false, false, false},
    {isotp_drop_cf, "isotp_drop_cf", kWire, false, false, true, false, false},
    {isotp_repeat_cf, "isotp_repeat_cf", kWire, false, false, true, false, false},
    {isotp_bad_sn, "isotp_bad_sn", kWire, false, false, true, false, false},
    {isotp_fc_overflow, "isotp_fc_overflow", kWire, false, false, true, false, false},
    {isotp_fc_wait, "isotp_fc_wait", kWire, false, false, true, false, false},
    {can_silence, "can_silence", kWire, false, false, true, false, false},
    {lpt_lose_steps, "lpt_lose_steps", kWire, false, false, false, true, false},
    {lpt_jam, "lpt_jam", kWire, false, false, false, true, false},
}};

constexpr bool catalogue_is_in_enum_order() {
  for (std::size_t i = 0; i < kCatalogue.size(); ++i) {
    if (static_cast<std::size_t>(kCatalogue[i].kind) != i) return false;
  }
  return true;
}
static_assert(catalogue_is_in_enum_order());

constexpr std::array<std::string_view, 4> kTransportNames{"tcp", "serial", "can", "lpt"};

}  // namespace

const FaultKindInfo& info(FaultKind kind) { return kCatalogue.at(static_cast<std::size_t>(kind)); }

std::string_view fault_name(FaultKind kind) { return info(kind).name; }

std::optional<FaultKind> fault_kind_from_name(std::string_view name) {
  for (const FaultKindInfo& entry : kCatalogue) {
    if (entry.name == name) return entry.kind;
  }
  return std::nullopt;
}

bool applies_to(FaultKind kind, Transport transport) {
  const FaultKindInfo& entry = info(kind);
  switch (transport) {
    case Transport::tcp: return entry.tcp;
    case Transport::serial: return entry.serial;
    case Transport::can: return entry.can;
    case Transport::lpt: return entry.lpt;
  }
  return false;
}

bool accepts(FaultKind kind, FaultParam param) {
  switch (param) {
    case FaultParam::sector_range: return kind == blind;
    case FaultParam::fraction: return kind == blind || kind == window_dirt;
    case FaultParam::delay_s: return kind == delay_reply;
    case FaultParam::bytes_kept: return kind == truncate_reply;
    case FaultParam::bytes: return kind == garbage;
    case FaultParam::bytes_per_s: return kind == bandwidth;
    case FaultParam::off_s: return kind == power_cycle;
  }
  return false;
}

std::string_view transport_name(Transport transport) {
  return kTransportNames.at(static_cast<std::size_t>(transport));
}

std::optional<Transport> transport_from_name(std::string_view name) {
  for (std::size_t i = 0; i < kTransportNames.size(); ++i) {
    if (kTransportNames[i] == name) return static_cast<Transport>(i);
  }
  return std::nullopt;
}

std::string_view all_fault_names() {
  return "motor_stall, motor_overspeed, encoder_error, power_cycle, reset_spontaneous, blind, "
         "window_dirt, drop_reply, delay_reply, duplicate_reply, truncate_reply, corrupt_checksum, "
         "garbage, tcp_reset, tcp_stall, bandwidth, isotp_drop_cf, isotp_repeat_cf, isotp_bad_sn, "
         "isotp_fc_overflow, isotp_fc_wait, can_silence, lpt_lose_steps, lpt_jam";
}

}  // namespace ldoem::faults
