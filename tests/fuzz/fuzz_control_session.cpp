// libFuzzer: bytes from a control-socket client -> line assembler -> request handling against a
// target that accepts everything. Every line must get exactly one reply line that is a JSON
// object with "return" or "error"; nothing may throw or crash.
//
// Issue 27: every fault the grammar accepts must stay inside the documented bounds of the values
// that size memory or time (docs/robustness.md), and the target builds what such a fault makes
// the daemon build (a garbage burst). Two invariants are asserted inside the target, so that a
// bound that slips is a crash here and not a slow test: the peak RSS (getrusage maxrss) grows by
// at most kMaxRssGrowthKib over the first input's, and one input takes at most kMaxInputCpuS of
// CPU time (CPU, not wall time: a loaded machine does not trip it).
#include <sys/resource.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string_view>

#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/control_socket/line_assembler.hpp"
#include "ldoem/faults/fault_scheduler.hpp"
#include "ldoem/faults/fault_spec.hpp"

namespace {

// ASan's quarantine alone holds up to 256 MiB of freed memory: 1 GiB leaves room for it and
// for libFuzzer's corpus, and is far below what a slipped bound costs (garbage of 4 GiB).
constexpr long kMaxRssGrowthKib = 1024 * 1024;
constexpr double kMaxInputCpuS = 2.0;

void check_bounds(const ldoem::faults::FaultSpec& spec) {
  using namespace ldoem::faults;
  const auto seconds = [](ldoem::base::SimTime t) { return std::chrono::duration<double>(t).count(); };
  if (spec.garbage_bytes > kMaxGarbageBytes || spec.bytes_per_s > kMaxBytesPerSecond) std::abort();
  if (seconds(spec.delay) > kMaxDelaySeconds || seconds(spec.off) > kMaxFaultSeconds) std::abort();
  if (spec.duration && seconds(*spec.duration) > kMaxFaultSeconds) std::abort();
  if (spec.count && *spec.count > 1'000'000'000'000ULL) std::abort();
  if (const auto* at = std::get_if<TriggerAt>(&spec.trigger); at && seconds(at->at) > kMaxFaultSeconds) std::abort();
  // What the daemon builds for each telegram a garbage fault precedes.
  if (spec.kind == FaultKind::garbage && fault_garbage(1, 1, spec.garbage_bytes).size() != spec.garbage_bytes) {
    std::abort();
  }
}

class AcceptingTarget final : public ldoem::control_socket::ControlTarget {
 public:
  ldoem::control_socket::CommandResult inject_fault(const ldoem::faults::FaultSpec& spec) override {
    check_bounds(spec);
    return nlohmann::json{{"id", ldoem::faults::describe(spec).size()}};
  }
  ldoem::control_socket::CommandResult clear_fault(std::optional<std::uint64_t>) override { return nlohmann::json::object(); }
  nlohmann::json query_faults() override { return nlohmann::json::array(); }
  nlohmann::json query_status() override { return nlohmann::json::object(); }
  void quit() override {}
};

long max_rss_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

double cpu_s() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const long first_rss_kib = max_rss_kib();
  const double started = cpu_s();
  AcceptingTarget target;
  ldoem::control_socket::LineAssembler lines(4096);
  std::vector<ldoem::control_socket::AssembledLine> out;
  lines.feed(std::string_view(reinterpret_cast<const char*>(data), size), out);
  for (const auto& line : out) {
    if (line.too_long) continue;
    const std::string reply = ldoem::control_socket::handle_line(line.text, target);
    const nlohmann::json parsed = nlohmann::json::parse(reply, nullptr, false);
    if (parsed.is_discarded() || !parsed.is_object() || (!parsed.contains("return") && !parsed.contains("error"))) {
      std::abort();
    }
    if (reply.find('\n') != std::string::npos) std::abort();
  }
  if (const double spent = cpu_s() - started; spent > kMaxInputCpuS) {
    std::fprintf(stderr, "fuzz_control_session: one input took %.2f s of CPU\n", spent);
    std::abort();
  }
  if (const long grown = max_rss_kib() - first_rss_kib; grown > kMaxRssGrowthKib) {
    std::fprintf(stderr, "fuzz_control_session: peak RSS grew %ld KiB\n", grown);
    std::abort();
  }
  return 0;
}
