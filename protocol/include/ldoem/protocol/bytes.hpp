// Byte views; big-endian WORDs at fixed offsets (spec 2.1). Framers assemble theirs byte by byte.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ldoem::protocol {

using Bytes = std::vector<std::uint8_t>;
using ByteView = std::span<const std::uint8_t>;

// Spec 2.1: every WORD goes most-significant byte first.
constexpr std::uint16_t read_word_be(ByteView bytes, std::size_t offset) {
  return static_cast<std::uint16_t>((bytes[offset] << 8) | bytes[offset + 1]);
}

constexpr std::uint32_t read_u32_be(ByteView bytes, std::size_t offset) {
  return (std::uint32_t{bytes[offset]} << 24) | (std::uint32_t{bytes[offset + 1]} << 16) |
         (std::uint32_t{bytes[offset + 2]} << 8) | std::uint32_t{bytes[offset + 3]};
}

inline void append_word_be(Bytes& out, std::uint16_t word) {
  out.push_back(static_cast<std::uint8_t>(word >> 8));
  out.push_back(static_cast<std::uint8_t>(word & 0xFF));
}

inline void append_u32_be(Bytes& out, std::uint32_t value) {
  append_word_be(out, static_cast<std::uint16_t>(value >> 16));
  append_word_be(out, static_cast<std::uint16_t>(value & 0xFFFF));
}

}  // namespace ldoem::protocol
