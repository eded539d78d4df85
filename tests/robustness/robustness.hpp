// What every robustness test checks at its end, and the small pieces they share.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "daemon_process.hpp"
#include "host_link.hpp"

namespace ldoem::daemon::test {

// Resident memory may grow to at most twice the start plus this much (allocator slack, buffers).
inline constexpr std::uint64_t kRssSlackKib = 32 * 1024;

// A daemon for a robustness test: minimal scene, flash in memory, a hard --timeout.
struct HostileRun {
  TempDir dir;
  std::optional<DaemonProcess> process;
  std::uint64_t start_rss_kib = 0;

  explicit HostileRun(std::vector<std::string> transport_arguments);
  // Starts, waits for "ready" and records the resident memory at start. Fails the test otherwise.
  ::testing::AssertionResult ready();
};

// Alive, and VmRSS <= 2 x start + kRssSlackKib.
::testing::AssertionResult still_healthy(DaemonProcess& process, std::uint64_t start_rss_kib);

// Deterministic garbage (fixed seed per test, so a failure can be replayed).
Bytes random_bytes(std::mt19937_64& generator, std::size_t count);

// LDOEM_FLOOD_SECONDS, or `fallback` (CI: 30 s).
double flood_seconds(double fallback = 30.0);

// GET_STATUS in IDLE as the reply the daemon must still give (D4 power-up, spec 7.2).
Bytes idle_status_reply();

}  // namespace ldoem::daemon::test
