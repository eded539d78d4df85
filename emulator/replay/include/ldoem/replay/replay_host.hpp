// ldoem-replay's loop: the emulator's endpoints (emulator/endpoints, opened from the daemon's
// endpoint registry) with a ReplayDevice behind them instead of a control unit (design.md:
// "Replaying a capture is a different device behind the same endpoints"). Time runs on the wall
// clock; the recorded delays are scaled by --speed inside the ReplayDevice. Telegrams due for a
// connection leave in order, one at a time once the endpoint is no longer busy with the previous
// one (D10); a connection that closes forgets what was still due for it.
#pragma once

#include <memory>
#include <ostream>

#include "ldoem/base/expected.hpp"
#include "ldoem/replay/replay_device.hpp"
#include "ldoem/replay/replay_options.hpp"

namespace ldoem::replay {

struct ReplayStartFailure {
  int exit_code = 2;
  std::string message;
};

class ReplayHost {
 public:
  // Opens every endpoint the options name, prints their lines and `ready` on `out`.
  static base::Expected<std::unique_ptr<ReplayHost>, ReplayStartFailure> create(
      const ReplayOptions& options, ReplayDevice device, std::ostream& out, std::ostream& log);
  ~ReplayHost();
  ReplayHost(const ReplayHost&) = delete;
  ReplayHost& operator=(const ReplayHost&) = delete;

  // Until SIGINT/SIGTERM (128 + signal), --timeout (0) or a loop failure (1).
  int run();
  const ReplayCounters& counters() const;

  struct Impl;

 private:
  explicit ReplayHost(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::replay
