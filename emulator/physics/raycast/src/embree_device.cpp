#include "embree_device.hpp"

#include <stdexcept>

namespace ldoem::raycast::detail {
namespace {

void report_device_error(void* user, RTCError code, const char* text) {
  auto* last = static_cast<std::string*>(user);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (text ? text : "");
}

}  // namespace

RTCDevice new_embree_device(const char* config, std::string& last_error) {
  RTCDevice device = rtcNewDevice(config);
  if (device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  rtcSetDeviceErrorFunction(device, report_device_error, &last_error);
  return device;
}

}  // namespace ldoem::raycast::detail
