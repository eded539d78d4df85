// Differential fuzzer (issue 26): the input bytes choose a small scene and a batch of rays
// biased towards what breaks ray casters (cases.hpp); both casters answer every ray and each
// answer is judged against the exact oracle within the bounds of docs/numerics.md (judge.hpp).
// Invariants: the oracle's object unless within the tie bound, the range within its bound,
// never NaN or infinity, a miss exactly when the oracle misses (within the bound at the reach,
// a tangent or an edge). A violation prints the case and aborts, so libFuzzer keeps the input.
// With LDOEM_NUMERICS_STATS=FILE the tallies of the whole run are written there at exit
// (scripts/numerics-report reads them).
#include "differential.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace {

// Never destroyed: write_totals runs at exit, after the destructors of statics built later
// than its registration, and libFuzzer may end the process from its timer while an input runs.
ldoem::oracle::Stats& totals() {
  static auto* stats = new ldoem::oracle::Stats;
  return *stats;
}

void write_totals() {
  if (const char* path = std::getenv("LDOEM_NUMERICS_STATS")) std::ofstream(path) << totals().text();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(write_totals);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 8192) return 0;
  ldoem::oracle::Stats stats;
  ldoem::oracle::run_case(ldoem::oracle::make_case({data, size}), stats);
  if (stats.fault_count() > 0) {
    std::fputs(stats.text().c_str(), stderr);
    std::abort();
  }
  totals().merge(stats);
  return 0;
}
