// The D11 fault catalogue: every fault the emulator can inject, what it is (a device fault the
// LD-OEM would report, or a wire fault a cable, bus or network does to correct telegrams), the
// transports it applies to and the parameters it takes. Names are the ones scenes and the
// control socket use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string_view>

#include "ldoem/protocol/transport.hpp"

// The catalogue is this one list, a row per kind:
//
//   ROW(kind, class, extent, (transports it applies to), (parameters it takes))
//
// The FaultKind enum below and the catalogue in fault_kind.cpp (and from it every name list,
// the Python package's table included) are expanded from it, so a new kind is one row here and
// nothing else to keep in step. It is a macro because nothing else in C++ makes both an enum's
// enumerators and a table of their names and properties from one list; everything built from it
// is ordinary code. `extent` is how long an entry without `duration_s` or `count` acts
// (FaultExtent below). Device faults act on the device itself, whatever transport the host uses,
// so their transport set is empty. Transport and parameter names are protocol::Transport's and
// FaultParam's enumerators. Comments in the list must be /* */: a // comment would swallow the
// line continuation.
#define LDOEM_FAULT_CATALOGUE(ROW)                                                                 \
  /* Device faults (D11): status nibbles, modes, ranges. */                                        \
  ROW(motor_stall,       device, until_cleared, (),                  ())                           \
  ROW(motor_overspeed,   device, until_cleared, (),                  ())                           \
  ROW(encoder_error,     device, until_cleared, (),                  ())                           \
  ROW(power_cycle,       device, one_shot,      (),                  (off_s))                      \
  ROW(reset_spontaneous, device, one_shot,      (),                  ())                           \
  ROW(blind,             device, until_cleared, (),                  (sector_range, fraction))     \
  ROW(window_dirt,       device, until_cleared, (),                  (fraction))                   \
  /* Wire faults on any telegram transport. */                                                     \
  ROW(drop_reply,        wire,   count_one,     (tcp, serial, can),  ())                           \
  ROW(delay_reply,       wire,   count_one,     (tcp, serial, can),  (delay_s))                    \
  ROW(duplicate_reply,   wire,   count_one,     (tcp, serial, can),  ())                           \
  ROW(truncate_reply,    wire,   count_one,     (tcp, serial, can),  (bytes_kept))                 \
  ROW(garbage,           wire,   count_one,     (tcp, serial, can),  (bytes))                      \
  /* CAN frames carry their own CRC (D1): the checksum D11 corrupts is TCP's XOR or serial's. */   \
  ROW(corrupt_checksum,  wire,   count_one,     (tcp, serial),       ())                           \
  /* TCP only. */                                                                                  \
  ROW(tcp_reset,         wire,   count_one,     (tcp),               ())                           \
  ROW(tcp_stall,         wire,   until_cleared, (tcp),               ())                           \
  ROW(bandwidth,         wire,   until_cleared, (tcp),               (bytes_per_s))                \
  /* CAN (ISO-TP) only. */                                                                         \
  ROW(isotp_drop_cf,     wire,   count_one,     (can),               ())                           \
  ROW(isotp_repeat_cf,   wire,   count_one,     (can),               ())                           \
  ROW(isotp_bad_sn,      wire,   count_one,     (can),               ())                           \
  ROW(isotp_fc_overflow, wire,   count_one,     (can),               ())                           \
  ROW(isotp_fc_wait,     wire,   until_cleared, (can),               ())                           \
  ROW(can_silence,       wire,   until_cleared, (can),               ())                           \
  /* The pseudo-LPT stepper port only. */                                                          \
  ROW(lpt_lose_steps,    wire,   count_one,     (lpt),               ())                           \
  ROW(lpt_jam,           wire,   until_cleared, (lpt),               ())

namespace ldoem::faults {

#define LDOEM_FAULT_ENUMERATOR(kind, ...) kind,
#define LDOEM_FAULT_COUNT_ONE(...) +1
enum class FaultKind : std::uint8_t { LDOEM_FAULT_CATALOGUE(LDOEM_FAULT_ENUMERATOR) };
inline constexpr std::size_t kFaultKindCount = 0 LDOEM_FAULT_CATALOGUE(LDOEM_FAULT_COUNT_ONE);
#undef LDOEM_FAULT_ENUMERATOR
#undef LDOEM_FAULT_COUNT_ONE

enum class FaultClass : std::uint8_t { device, wire };

// How long a fault whose entry gives neither `duration_s` nor `count` acts.
enum class FaultExtent : std::uint8_t {
  one_shot,       // once when triggered (power_cycle, reset_spontaneous); it takes neither field
  count_one,      // as if `count: 1`: one telegram (lpt_lose_steps: one step)
  until_cleared,  // until cleared: device faults, and wire faults that are a state of the link
                  // rather than an event on a telegram (tcp_stall, can_silence, lpt_jam, ...)
};

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

// The parameters a kind accepts, as TransportSet holds transports.
class FaultParamSet {
 public:
  constexpr FaultParamSet() = default;
  constexpr FaultParamSet(std::initializer_list<FaultParam> members) {
    for (FaultParam member : members) bits_ |= bit(member);
  }
  constexpr bool contains(FaultParam param) const { return (bits_ & bit(param)) != 0; }
  constexpr bool operator==(const FaultParamSet&) const = default;

 private:
  static constexpr std::uint8_t bit(FaultParam param) {
    return static_cast<std::uint8_t>(1U << static_cast<unsigned>(param));
  }
  std::uint8_t bits_ = 0;
};

struct FaultKindInfo {
  FaultKind kind;
  std::string_view name;
  FaultClass fault_class;
  TransportSet transports;  // the transports it applies to (empty: a device fault)
  FaultExtent extent;
  FaultParamSet params;
};

const FaultKindInfo& info(FaultKind kind);
std::string_view fault_name(FaultKind kind);
std::optional<FaultKind> fault_kind_from_name(std::string_view name);
bool applies_to(FaultKind kind, Transport transport);
bool accepts(FaultKind kind, FaultParam param);
// "motor_stall, motor_overspeed, ..." for error messages.
std::string_view all_fault_names();

}  // namespace ldoem::faults
