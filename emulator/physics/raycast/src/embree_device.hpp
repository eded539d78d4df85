// How both Embree casters open their device: one place creates it and routes its errors into a
// string that the caster throws after a build. Internal to ldoem_raycast.
#pragma once

#include <embree3/rtcore.h>

#include <string>

namespace ldoem::raycast::detail {

// A new Embree device with `config` (nullptr for Embree's defaults) whose errors overwrite
// `last_error` as "Embree error CODE: text"; `last_error` must outlive the device. Throws
// std::runtime_error when Embree cannot create one.
[[nodiscard]] RTCDevice new_embree_device(const char* config, std::string& last_error);

}  // namespace ldoem::raycast::detail
