// Transitional: the descriptor owner is base::UniqueFd (ldoem/base/unique_fd.hpp). This name
// stays only until the daemon's endpoints use base's directly; new code includes base's header.
#pragma once

#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {

using base::UniqueFd;

}  // namespace ldoem::io
