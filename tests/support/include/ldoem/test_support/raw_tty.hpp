// A pty the daemon made (serial or LPT), opened as a host opens it: raw, so that no line
// discipline on the test's side turns the protocol's bytes into something else.
#pragma once

#include <string>

namespace ldoem::test_support {

// The descriptor, or -1; `extra_flags` is added to O_RDWR | O_NOCTTY | O_CLOEXEC (O_NONBLOCK).
int open_raw(const std::string& path, int extra_flags = 0);

}  // namespace ldoem::test_support
