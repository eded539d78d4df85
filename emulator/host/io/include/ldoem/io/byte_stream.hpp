// What a non-blocking read of a byte stream (pty, TCP) gives back.
#pragma once

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::io {

struct Received {
  protocol::Bytes bytes;     // empty when nothing was waiting
  bool peer_closed = false;  // the other side closed: no more bytes will come
};

}  // namespace ldoem::io
