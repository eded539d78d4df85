#include "ldoem/faults/fault_kind.hpp"

#include <array>

namespace ldoem::faults {
namespace {

using enum FaultKind;
constexpr FaultClass kDevice = FaultClass::device;
constexpr FaultClass kWire = FaultClass::wire;
constexpr Transport kTcp = Transport::tcp;
constexpr Transport kSerial = Transport::serial;
constexpr Transport kCan = Transport::can;
constexpr Transport kLpt = Transport::lpt;

// Indexed by FaultKind. D11 lists the transports of each wire fault; device faults act on the
// device itself, whatever transport the host uses.
constexpr std::array<FaultKindInfo, kFaultKindCount> kCatalogue{{
    {motor_stall, "motor_stall", kDevice, {}, false},
    {motor_overspeed, "motor_overspeed", kDevice, {}, false},
    {encoder_error, "encoder_error", kDevice, {}, false},
    {power_cycle, "power_cycle", kDevice, {}, true},
    {reset_spontaneous, "reset_spontaneous", kDevice, {}, true},
    {blind, "blind", kDevice, {}, false},
    {window_dirt, "window_dirt", kDevice, {}, false},
    {drop_reply, "drop_reply", kWire, {kTcp, kSerial, kCan}, false},
    {delay_reply, "delay_reply", kWire, {kTcp, kSerial, kCan}, false},
    {duplicate_reply, "duplicate_reply", kWire, {kTcp, kSerial, kCan}, false},
    {truncate_reply, "truncate_reply", kWire, {kTcp, kSerial, kCan}, false},
    // CAN frames carry their own CRC (D1): the checksum D11 corrupts is TCP's XOR or serial's CRC.
    {corrupt_checksum, "corrupt_checksum", kWire, {kTcp, kSerial}, false},
    {garbage, "garbage", kWire, {kTcp, kSerial, kCan}, false},
    {tcp_reset, "tcp_reset", kWire, {kTcp}, false},
    {tcp_stall, "tcp_stall", kWire, {kTcp}, false},
    {bandwidth, "bandwidth", kWire, {kTcp}, false},
    {isotp_drop_cf, "isotp_drop_cf", kWire, {kCan}, false},
    {isotp_repeat_cf, "isotp_repeat_cf", kWire, {kCan}, false},
    {isotp_bad_sn, "isotp_bad_sn", kWire, {kCan}, false},
    {isotp_fc_overflow, "isotp_fc_overflow", kWire, {kCan}, false},
    {isotp_fc_wait, "isotp_fc_wait", kWire, {kCan}, false},
    {can_silence, "can_silence", kWire, {kCan}, false},
    {lpt_lose_steps, "lpt_lose_steps", kWire, {kLpt}, false},
    {lpt_jam, "lpt_jam", kWire, {kLpt}, false},
}};

constexpr bool catalogue_is_in_enum_order() {
  for (std::size_t i = 0; i < kCatalogue.size(); ++i) {
    if (static_cast<std::size_t>(kCatalogue[i].kind) != i) return false;
  }
  return true;
}
static_assert(catalogue_is_in_enum_order());

}  // namespace

const FaultKindInfo& info(FaultKind kind) { return kCatalogue.at(static_cast<std::size_t>(kind)); }

std::string_view fault_name(FaultKind kind) { return info(kind).name; }

std::optional<FaultKind> fault_kind_from_name(std::string_view name) {
  for (const FaultKindInfo& entry : kCatalogue) {
    if (entry.name == name) return entry.kind;
  }
  return std::nullopt;
}

bool applies_to(FaultKind kind, Transport transport) { return info(kind).transports.contains(transport); }

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

std::string_view all_fault_names() {
  return "motor_stall, motor_overspeed, encoder_error, power_cycle, reset_spontaneous, blind, "
         "window_dirt, drop_reply, delay_reply, duplicate_reply, truncate_reply, corrupt_checksum, "
         "garbage, tcp_reset, tcp_stall, bandwidth, isotp_drop_cf, isotp_repeat_cf, isotp_bad_sn, "
         "isotp_fc_overflow, isotp_fc_wait, can_silence, lpt_lose_steps, lpt_jam";
}

}  // namespace ldoem::faults
