// Reads what can-utils' isotpdump prints (Debian 12's can-utils 2020.11, options -s/-d, with or
// without -c colour and -a ASCII) and puts the messages back together, so a test can hold the
// reference decoder's view of the bus against what our driver received (D1). Pure: text in,
// values out.
//
// Line grammar as isotpdump prints it (colour codes, when -c is given, are stripped first):
//   IFACE  ID  [DLC]  [SF] ln: LEN  data: HH HH ..  [-  'ASCII']
//   IFACE  ID  [DLC]  [FF] ln: LEN  data: HH ..       LEN from the 12-bit field or the 32-bit escape
//   IFACE  ID  [DLC]  [CF] sn: N    data: HH ..       N: the sequence nibble, one hex digit
//   IFACE  ID  [DLC]  [FC] FC: S = NAME # BS: B ... # STmin: 0xHH = ...
// Examples (each one is a test case):
//   " vcan0  6C0  [3]  [SF] ln: 2    data: 01 02                 -  '..'"
//   " vcan0  6C1  [8]  [FF] ln: 4096 data: 01 02                 -  '..'"
//   " vcan0  6C0  [3]  [FC] FC: 0 = CTS # BS: 0 = off # STmin: 0x00 = 0 ms"
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::interop {

struct DumpedFrame {
  std::uint32_t id = 0;
  std::uint8_t dlc = 0;
  protocol::IsoTpFrameType type = protocol::IsoTpFrameType::single_frame;
  std::optional<std::uint64_t> announced_length;  // SF and FF: "ln:"
  std::optional<std::uint8_t> sequence;           // CF: "sn:"
  protocol::Bytes data;                           // SF, FF, CF: the "data:" bytes
  std::optional<std::uint8_t> flow_status;        // FC: 0 CTS, 1 WAIT, 2 OVFLW
  std::optional<std::uint8_t> block_size;         // FC
  std::optional<std::uint8_t> st_min_byte;        // FC
};

// "line 3: no [SF]/[FF]/[CF]/[FC] field: <the line>"
using DumpError = std::string;

// Every non-empty line must be a frame line; the first one that is not is the error.
base::Expected<std::vector<DumpedFrame>, DumpError> parse_isotpdump(std::string_view text);

struct DumpedMessage {
  std::uint32_t id = 0;
  protocol::Bytes payload;
  std::size_t frames = 0;  // SF: 1; FF + CFs
};

// Messages per identifier in the order they completed, and every broken sequence the way our
// receiver would count it (D1): a CF with the wrong sequence number or without an FF, an SF or
// FF that interrupts a message. Trailing bytes past the announced length (padding) are cut.
struct Reassembly {
  std::vector<DumpedMessage> messages;
  std::vector<std::string> problems;  // "6C1: CF sn 3 where 2 was due"
  std::vector<std::uint32_t> unfinished_ids;  // a message still short of its length at the end
};

Reassembly reassemble(const std::vector<DumpedFrame>& frames);

}  // namespace ldoem::interop
