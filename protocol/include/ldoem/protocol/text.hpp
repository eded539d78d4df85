// One-line text form of a telegram payload, for logs, dump helpers and test tables
// (design.md convention 1). format_telegram and parse_telegram are inverse on every payload.
//
// Grammar (tokens separated by single spaces; hex digits either case on input, lowercase on
// output):
//   telegram := [ code { " " word } [ " " byte ] ]
//   code     := NAME            a request of spec 3.2, e.g. GET_PROFILE, or SERVICE_FAILURE
//             | NAME " reply"   the same service with bit 15 set (spec 2.2)
//             | word            any other code, as 4 hex digits
//   word     := 4 hex digits    one parameter WORD, big-endian
//   byte     := 2 hex digits    a last odd byte (only text replies have odd lengths)
// A payload shorter than 2 bytes is the empty string or a lone byte.
//
// Examples (each one is a test case):
//   "GET_PROFILE 0000 39ff"             03 01 00 00 39 ff
//   "GET_STATUS"                        01 02
//   "GET_STATUS reply 0000 0001"        81 02 00 00 00 01
//   "SERVICE_FAILURE 0501 0001"         ff 00 05 01 00 01
//   "0500 0001"                         05 00 00 01
//   "GET_IDENTIFICATION reply 4c44 2d"  81 01 4c 44 2d
//   ""                                  (empty payload)
#pragma once

#include <string>
#include <string_view>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::protocol {

std::string format_telegram(ByteView payload);

// bad_text for anything outside the grammar (unknown name, wrong digit count, double space).
base::Expected<Bytes, DecodeError> parse_telegram(std::string_view text);

}  // namespace ldoem::protocol
