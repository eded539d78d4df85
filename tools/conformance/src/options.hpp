// The command line of ldoem-conformance, parsed by a pure function (design.md convention 1).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::conformance {

// Exit codes (design.md convention 1).
inline constexpr int kExitAllPassed = 0;
inline constexpr int kExitFailed = 1;      // a case failed, or the endpoint could not be opened
inline constexpr int kExitUsageError = 2;  // bad option

enum class Target : std::uint8_t {
  emulator,  // every byte as spec 7.2 and the D-decisions fix it
  device,    // only the positions spec 7.2 confirms (its last column), so a real LD can pass
};

struct SuiteOptions {
  std::optional<driver::Endpoint> endpoint;  // required unless --list or --help
  Target target = Target::emulator;
  double time_scale = 1.0;       // the endpoint's simulated seconds per wall second (D7)
  bool virtual_time = false;     // the endpoint's clock is not tied to the wall clock at all
  bool strict_timing = false;    // a wall-clock failure on a busy machine is FAIL, not INCONCLUSIVE
  std::chrono::milliseconds reply_timeout{5000};  // spec 6: S1 waits 5 s for a reply
  std::vector<std::string> filters;   // globs over case names; empty = all
  std::vector<std::string> excludes;  // globs over case names left out after the filters
  bool list = false;
  bool help = false;
  bool help_all = false;  // --help-all: the full usage text; --help prints the brief one
  bool version = false;  // --version: print base::version_line and exit 0
  bool verbose = false;               // print every telegram sent and received on stderr
  std::optional<std::string> vectors_file;  // instead of the compiled-in copy
  // --against CAPTURE: replay the capture's requests and compare the replies field by field
  // (docs/conformance.md, "Against a capture") instead of running the cases.
  std::optional<std::string> against;
  std::optional<std::uint16_t> against_tcp_port;  // --port: the device's port in the capture; unset: detected
  std::vector<std::string> masks;  // field-name globs left out of the comparison
  std::optional<std::string> record;  // write the run's telegrams to this capture file
  std::optional<std::string> completion_script;  // --completion bash: print it and exit 0
};

// --mask-times and --mask-counters stand for these globs.
inline const std::vector<std::string> kTimeFieldMasks{"*clock_ms", "profile.sector*.tstart", "profile.sector*.tend"};
inline const std::vector<std::string> kCounterFieldMasks{"profile.sent", "profile.count"};

struct SuiteUsageError {
  std::string message;  // one line naming the option
};

// `arguments` excludes argv[0]. Values follow their option as the next argument or after '='
// (parsed with CLI11, base/command_line.hpp).
[[nodiscard]] base::Expected<SuiteOptions, SuiteUsageError> parse_options(std::span<const std::string_view> arguments);

std::string usage_text(std::string_view program_name);
// What --help prints: a screen of usage_text (base::brief_help).
std::string brief_usage_text(std::string_view program_name);

// "tcp", "can" or "serial": the first part of every case name.
std::string transport_prefix(const driver::Endpoint& endpoint);

// fnmatch(3) semantics without FNM_PATHNAME: `*` also matches `/`. True when `filters` is empty.
bool matches_any(const std::vector<std::string>& filters, std::string_view name);

}  // namespace ldoem::conformance
