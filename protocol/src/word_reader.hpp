// Private helper: reads big-endian WORDs from a payload with bounds checks (spec 2.1).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::protocol::detail {

class WordReader {
 public:
  explicit WordReader(ByteView bytes, std::size_t offset = 0) : bytes_(bytes), offset_(offset) {}

  std::size_t remaining_bytes() const { return bytes_.size() - offset_; }
  std::size_t remaining_words() const { return remaining_bytes() / 2; }
  std::size_t offset() const { return offset_; }

  // Precondition: remaining_bytes() >= 2.
  std::uint16_t word() {
    const std::uint16_t value = read_word_be(bytes_, offset_);
    offset_ += 2;
    return value;
  }
  std::optional<std::uint16_t> try_word() {
    if (remaining_bytes() < 2) return std::nullopt;
    return word();
  }
  // Precondition: remaining_bytes() >= count.
  ByteView take(std::size_t count) {
    const ByteView view = bytes_.subspan(offset_, count);
    offset_ += count;
    return view;
  }

 private:
  ByteView bytes_;
  std::size_t offset_;
};

}  // namespace ldoem::protocol::detail
