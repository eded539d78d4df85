// Helpers shared by the driver tests: hex text, the spec section 7 vectors, frame payloads,
// protocol's encoder for the telegrams the spec has no row for.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/messages.hpp"

namespace ldoem::driver::test {

using protocol::Bytes;

// "02 55 53 50" -> bytes; spaces optional.
inline Bytes hex_bytes(const std::string& text) {
  Bytes out;
  std::string digits;
  for (char c : text) {
    if (c != ' ') {
      digits.push_back(c);
    }
  }
  for (std::size_t i = 0; i + 1 < digits.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoul(digits.substr(i, 2), nullptr, 16)));
  }
  return out;
}

inline std::string hex_text(const Bytes& bytes) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string text;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i != 0) {
      text.push_back(' ');
    }
    text.push_back(kDigits[bytes[i] >> 4]);
    text.push_back(kDigits[bytes[i] & 0xF]);
  }
  return text;
}

// The payload inside a whole TCP frame (spec 4.1): bytes 8 .. size-1.
inline Bytes tcp_payload(const Bytes& frame) { return Bytes(frame.begin() + 8, frame.end() - 1); }

inline Bytes encoded(const protocol::Response& response) { return protocol::encode_response(response); }
inline Bytes encoded(const protocol::Request& request) { return protocol::encode_request(request); }

// tests/vectors/spec-section7.yaml, section by section, keyed by the row name.
struct SpecVectors {
  std::map<std::string, Bytes> tcp_requests;  // whole frames
  std::map<std::string, Bytes> tcp_replies;   // whole frames
  std::map<std::string, std::string> serial_requests;  // ASCII between STX and ETX

  static const SpecVectors& get() {
    static const SpecVectors vectors = load(LDOEM_VECTORS_FILE);
    return vectors;
  }

  const Bytes& request(const std::string& name) const { return at(tcp_requests, name); }
  const Bytes& reply(const std::string& name) const { return at(tcp_replies, name); }
  const std::string& serial(const std::string& name) const { return at(serial_requests, name); }

 private:
  template <class Map>
  static const typename Map::mapped_type& at(const Map& map, const std::string& name) {
    const auto found = map.find(name);
    if (found == map.end()) {
      throw std::out_of_range("no vector named `" + name + "` in " LDOEM_VECTORS_FILE);
    }
    return found->second;
  }

  static SpecVectors load(const std::string& path) {
    const YAML::Node root = YAML::LoadFile(path);
    SpecVectors vectors;
    for (const auto& row : root["tcp_requests"]) {
      vectors.tcp_requests[row["name"].as<std::string>()] = hex_bytes(row["frame"].as<std::string>());
    }
    for (const auto& row : root["tcp_replies"]) {
      vectors.tcp_replies[row["name"].as<std::string>()] = hex_bytes(row["frame"].as<std::string>());
    }
    for (const auto& row : root["serial_requests"]) {
      vectors.serial_requests[row["name"].as<std::string>()] = row["ascii"].as<std::string>();
    }
    return vectors;
  }
};

// GET_STATUS's reply with the sensor idle and the motor ok: the payload of spec 7.2's row.
inline const Bytes kStatusIdle = tcp_payload(SpecVectors::get().reply("GET_STATUS, IDLE, motor OK"));

}  // namespace ldoem::driver::test
