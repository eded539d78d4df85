// Differential fuzzer (issue 26): the input bytes choose a small scene and a batch of rays
// biased towards what breaks ray casters (cases.hpp); both casters answer every ray and each
// answer is judged against the exact oracle within the bounds of docs/numerics.md (judge.hpp).
// Invariants: the oracle's object unless within the tie bound, the range within its bound,
// never NaN or infinity, a miss exactly when the oracle misses (within the bound at the reach,
// a tangent or an edge). A violation prints the case and aborts, so libFuzzer keeps the input.
// With LDOEM_NUMERICS_STATS=FILE the tallies of the run so far are rewritten there after every
// input (scripts/numerics-report reads them). Not at exit: an atexit writer ran after the
// destructors of statics it read (AddressSanitizer: heap-use-after-free in Stats::merge, issue
// 26), and libFuzzer may end the process from its timer while an input runs anyway.
#include "differential.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace {

// Held by the function (never destroyed): nothing reads it once main has returned.
ldoem::oracle::Stats& totals() {
  static auto* stats = new ldoem::oracle::Stats;
  return *stats;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 8192) return 0;
  ldoem::oracle::Stats stats;
  ldoem::oracle::run_case(ldoem::oracle::make_case({data, size}), stats);
  if (stats.fault_count() > 0) {
    std::fputs(stats.text().c_str(), stderr);
    std::abort();
  }
  totals().merge(stats);
  if (const char* path = std::getenv("LDOEM_NUMERICS_STATS")) std::ofstream(path, std::ios::trunc) << totals().text();
  return 0;
}
