// Runs the selected cases in order against one endpoint and prints one line per case, then
// exactly `N passed, M failed`.
#pragma once

#include <ostream>

#include "options.hpp"
#include "vector_table.hpp"

namespace ldoem::conformance {

// The case names --list prints: for the given endpoint, else for every transport.
void list_cases(const SuiteOptions& options, const VectorTable& vectors, std::ostream& out);

// Returns the exit code (kExitAllPassed, kExitFailed).
int run_cases(const SuiteOptions& options, const VectorTable& vectors, std::ostream& out, std::ostream& err);

}  // namespace ldoem::conformance
