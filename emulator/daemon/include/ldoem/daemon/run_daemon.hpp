// ldoem-emud after its command line: load the scene (none with --replay), check the flash
// folders, open --record, start the daemon and run it; the exit code (design.md convention 1).
// ldoem-replay, the alias of `ldoem-emud --replay`, ends here too.
#pragma once

#include <string_view>

#include "ldoem/daemon/options.hpp"

namespace ldoem::daemon {

// `program` starts the lines it prints on stderr ("ldoem-emud: ...").
int run_daemon(std::string_view program, const Options& options);

}  // namespace ldoem::daemon
