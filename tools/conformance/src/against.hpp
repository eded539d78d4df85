// `ldoem-conformance --against CAPTURE` (docs/conformance.md): the capture's requests, sent in
// recorded order to any endpoint, and every reply compared with the recorded one field by field
// through the protocol codec (reply_fields.hpp). Replies are paired in order; profiles are paired
// with the profiles recorded after the same request, and a live stream's extra profiles are
// counted, not compared. Output: one PASS/FAIL line per exchange, the differing fields under a
// FAIL, then `N passed, M failed`.
#pragma once

#include <ostream>

#include "options.hpp"

namespace ldoem::conformance {

int run_against(const SuiteOptions& options, std::ostream& out, std::ostream& err);

}  // namespace ldoem::conformance
