// Every service code of spec section 3.2: service = (group << 8) | number, responses carry
// bit 15 (spec 2.2). SERVICE_FAILURE 0xFF00 comes from the paper and D2.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace ldoem::protocol {

enum class Service : std::uint16_t {
  // Status group 0x01
  get_identification = 0x0101,
  get_status = 0x0102,
  get_signal = 0x0104,
  set_signal = 0x0105,
  ld_register_application = 0x0106,  // layout unpublished (D2: reason 1)
  // Configuration group 0x02
  set_config = 0x0201,
  get_config = 0x0202,
  set_time_abs = 0x0203,
  set_time_rel = 0x0204,
  get_sync_clock = 0x0205,
  set_filter = 0x0209,
  set_function = 0x020A,
  get_function = 0x020B,
  // Measurement group 0x03
  get_profile = 0x0301,
  cancel_profile = 0x0302,
  // Working group 0x04
  do_reset = 0x0401,
  trans_idle = 0x0402,
  trans_rotate = 0x0403,
  trans_measure = 0x0404,
  // Routing group 0x06, File group 0x07, Monitor group 0x08: codes only (D2: reason 1)
  com_attach = 0x0601,
  com_detach = 0x0602,
  com_initialize = 0x0603,
  com_output = 0x0604,
  com_data = 0x0605,
  file_dir = 0x0701,
  file_save = 0x0702,
  file_load = 0x0703,
  file_delete = 0x0704,
  monitor_run = 0x0801,
  monitor_profile_log = 0x0802,
  // Response only (paper, D2)
  service_failure = 0xFF00,
};

// Spec 2.2: a response carries the request code with bit 15 set.
inline constexpr std::uint16_t kResponseBit = 0x8000;

constexpr std::uint16_t code_of(Service service) { return static_cast<std::uint16_t>(service); }
constexpr std::uint16_t response_code(std::uint16_t request_code) {
  return static_cast<std::uint16_t>(request_code | kResponseBit);
}
constexpr std::uint16_t response_code(Service service) { return response_code(code_of(service)); }
constexpr bool is_response(std::uint16_t code) { return (code & kResponseBit) != 0; }

// The service a request code names, if it is one of spec 3.2 (0xFF00 is not a request).
std::optional<Service> request_service(std::uint16_t code);

// True for the codes whose payload layout is unpublished (0x0106, 06xx, 07xx, 08xx): D2 answers
// them SERVICE_FAILURE reason 1.
bool has_unpublished_layout(Service service);

// True when service_name(code) names the code: a request of spec 3.2, its response, or 0xFF00.
bool is_known_code(std::uint16_t code);

// "GET_STATUS" for 0x0102, "GET_STATUS reply" for 0x8102, "SERVICE_FAILURE" for 0xFF00, and
// "unknown service" for a code that is_known_code rejects.
std::string_view service_name(std::uint16_t code);

// Inverse of service_name for request names and "<NAME> reply"; nullopt for anything else.
std::optional<std::uint16_t> service_code_from_name(std::string_view name);

}  // namespace ldoem::protocol
