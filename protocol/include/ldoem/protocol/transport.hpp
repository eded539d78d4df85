// The links a host reaches the device on, and one host connection over them: the one definition
// that the control unit (who a telegram came from), the fault catalogue (where a fault acts), the
// captures (which framing a recorded stream has) and the daemon's endpoints share, so nothing
// converts between copies.
#pragma once

#include <compare>
#include <initializer_list>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ldoem::protocol {

// TCP and serial carry framed telegrams capped at 5816 payload bytes; CAN carries ISO-TP
// messages without that cap; the LPT port carries no telegrams at all, only the stepper's
// bits, but faults and captures name it too.
enum class Transport : std::uint8_t { tcp, serial, can, lpt };
inline constexpr std::size_t kTransportCount = 4;

// "tcp", "serial", "can", "lpt": the names scenes, fault entries and the control socket use.
std::string_view transport_name(Transport transport);
std::optional<Transport> transport_from_name(std::string_view name);

// A set of transports, e.g. the ones a fault kind applies to.
class TransportSet {
 public:
  constexpr TransportSet() = default;
  constexpr TransportSet(std::initializer_list<Transport> members) {
    for (Transport member : members) bits_ |= bit(member);
  }
  constexpr bool contains(Transport transport) const { return (bits_ & bit(transport)) != 0; }
  constexpr bool empty() const { return bits_ == 0; }
  constexpr bool operator==(const TransportSet&) const = default;

 private:
  static constexpr std::uint8_t bit(Transport transport) {
    return static_cast<std::uint8_t>(1U << static_cast<unsigned>(transport));
  }
  std::uint8_t bits_ = 0;
};

// One host connection (a TCP session, a serial line, a CAN identifier pair). `index` is the
// daemon's number for it, unique per transport while the connection lives.
struct ConnectionId {
  Transport kind = Transport::tcp;
  std::uint32_t index = 0;
  auto operator<=>(const ConnectionId&) const = default;
};

// "tcp#3": how logs and events name a connection.
std::string to_string(ConnectionId connection);

}  // namespace ldoem::protocol
