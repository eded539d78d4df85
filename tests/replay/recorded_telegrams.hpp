// Telegrams both replay tests record and answer. One definition: the asan preset builds each
// test program as one unity file, where two file-local copies would collide.
#pragma once

#include <cstdint>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::replay::test {

inline const protocol::Bytes kGetStatus{0x01, 0x02};
inline const protocol::Bytes kStatusIdle{0x81, 0x02, 0, 0, 0, 0x01};
inline protocol::Bytes profile(std::uint8_t tag) { return protocol::Bytes{0x83, 0x01, 0x39, 0xFF, 0x00, tag}; }

}  // namespace ldoem::replay::test
