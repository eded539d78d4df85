// Shared helpers of the protocol tests: hex literals, readable failure output, and running a
// streaming decoder the three ways design.md convention 5 asks for.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ldoem/protocol/framing.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/text.hpp"

namespace ldoem::protocol {

// gtest printers: a failing comparison shows the telegram in its text form.
inline void PrintTo(const Request& request, std::ostream* os) {
  *os << '"' << format_telegram(encode_request(request)) << '"';
}
inline void PrintTo(const Response& response, std::ostream* os) {
  *os << '"' << format_telegram(encode_response(response)) << '"';
}
inline void PrintTo(DecodeError error, std::ostream* os) { *os << describe(error); }
inline void PrintTo(FailureReason reason, std::ostream* os) { *os << describe(reason); }
inline void PrintTo(const RequestError& error, std::ostream* os) {
  *os << "{code " << std::hex << error.request_code << std::dec << ", " << describe(error.reason) << ", "
      << describe(error.detail) << "}";
}
inline void PrintTo(const DeframerEvent& event, std::ostream* os) {
  if (const auto* telegram = std::get_if<Telegram>(&event)) {
    *os << "Telegram \"" << format_telegram(telegram->payload) << '"';
  } else {
    const auto& error = std::get<FramingError>(event);
    *os << "FramingError{" << describe(error.detail) << ", " << std::hex << error.request_code << std::dec << "}";
  }
}

}  // namespace ldoem::protocol

namespace ldoem::protocol::test {

// "02 55 53 50" (spaces optional) -> bytes. A malformed literal fails the calling test.
inline Bytes hex(std::string_view text) {
  Bytes bytes;
  int pending = -1;
  for (const char c : text) {
    if (c == ' ') continue;
    int digit = -1;
    if (c >= '0' && c <= '9') digit = c - '0';
    if (c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') digit = c - 'A' + 10;
    EXPECT_GE(digit, 0) << "bad hex literal: " << text;
    if (digit < 0) return {};
    if (pending < 0) {
      pending = digit;
    } else {
      bytes.push_back(static_cast<std::uint8_t>(pending * 16 + digit));
      pending = -1;
    }
  }
  EXPECT_LT(pending, 0) << "odd hex literal: " << text;
  return bytes;
}

inline Bytes ascii(std::string_view text) { return Bytes(text.begin(), text.end()); }

// STX text ETX, the serial wire form of a spec 7.4 row.
inline Bytes serial_wire(std::string_view body) {
  Bytes bytes;
  bytes.reserve(body.size() + 2);
  bytes.push_back(0x02);
  for (const char c : body) bytes.push_back(static_cast<std::uint8_t>(c));
  bytes.push_back(0x03);
  return bytes;
}

inline Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

// The payloads of the telegrams among a deframer's events, in order (framing errors left out).
inline std::vector<Bytes> telegrams_of(const std::vector<DeframerEvent>& events) {
  std::vector<Bytes> payloads;
  for (const auto& event : events) {
    if (const auto* telegram = std::get_if<Telegram>(&event)) payloads.push_back(telegram->payload);
  }
  return payloads;
}

// Runs a fresh decoder from `make()` over `stream` whole, byte by byte, and split in two at
// every offset; every run must give `expected`.
template <class MakeDecoder>
void expect_events_every_split(MakeDecoder make, const Bytes& stream, const std::vector<DeframerEvent>& expected) {
  {
    auto decoder = make();
    EXPECT_EQ(decoder.feed(stream), expected) << "whole";
  }
  {
    auto decoder = make();
    std::vector<DeframerEvent> events;
    for (const auto byte : stream) {
      for (auto& event : decoder.feed(ByteView(&byte, 1))) events.push_back(std::move(event));
    }
    EXPECT_EQ(events, expected) << "byte by byte";
  }
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    auto decoder = make();
    auto events = decoder.feed(ByteView(stream).first(split));
    for (auto& event : decoder.feed(ByteView(stream).subspan(split))) events.push_back(std::move(event));
    EXPECT_EQ(events, expected) << "split at " << split;
    if (events != expected) return;  // one report is enough
  }
}

// Reply payloads the framing and capture tests carry: GET_STATUS, TRANS_IDLE, GET_SYNC_CLOCK.
inline const Bytes kStatusReply = hex("81 02 00 00 00 01");
inline const Bytes kIdleReply = hex("84 02 00 00 00 01");
inline const Bytes kClockReply = hex("82 05 12 34");

inline DeframerEvent telegram(Bytes payload) { return Telegram{std::move(payload)}; }
inline DeframerEvent framing_error(DecodeError detail, std::uint16_t request_code = 0) {
  return FramingError{detail, request_code};
}

}  // namespace ldoem::protocol::test
