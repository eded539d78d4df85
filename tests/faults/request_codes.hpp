// The request codes the scheduler tests trigger faults on (spec 3.2), as the scheduler takes them.
#pragma once

#include <cstdint>

#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::faults::test {

constexpr auto kGetStatus = static_cast<std::uint16_t>(protocol::Service::get_status);
constexpr auto kGetProfile = static_cast<std::uint16_t>(protocol::Service::get_profile);

}  // namespace ldoem::faults::test
