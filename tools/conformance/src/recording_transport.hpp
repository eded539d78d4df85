// `--record FILE`: every telegram the suite sends and receives, written to a capture
// (docs/capture.md) with the wall time since the first transport opened. A lab records a real
// LD-OEM once this way and compares the emulator (or a later firmware) with `--against FILE`.
#pragma once

#include <memory>
#include <string>

#include "ldoem/driver/transport.hpp"
#include "ldoem/base/expected.hpp"
#include "options.hpp"

namespace ldoem::conformance {

// Opens the endpoint's transport; with options.record, wrapped so that it records. All
// transports opened in one run write to the same file, each as its own connection.
base::Expected<std::unique_ptr<driver::TelegramTransport>, std::string> open_suite_transport(const SuiteOptions& options);

}  // namespace ldoem::conformance
