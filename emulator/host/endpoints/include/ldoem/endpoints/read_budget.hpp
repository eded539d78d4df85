// How much one stream endpoint reads per loop round.
#pragma once

#include <cstddef>

namespace ldoem::endpoints {

// Bytes read from one stream per loop round: a chatty host cannot starve the others.
inline constexpr std::size_t kReadBudgetBytes = 65536;

}  // namespace ldoem::endpoints
