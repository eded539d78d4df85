#include "ldoem/protocol/service_codes.hpp"

#include <array>

namespace ldoem::protocol {
namespace {

struct NamedService {
  Service service;
  std::string_view name;        // spec 3.2 spelling
  std::string_view reply_name;  // the same with bit 15 set (spec 2.2)
};

constexpr std::array<NamedService, 31> kServiceNames{{
    {Service::get_identification, "GET_IDENTIFICATION", "GET_IDENTIFICATION reply"},
    {Service::get_status, "GET_STATUS", "GET_STATUS reply"},
    {Service::get_signal, "GET_SIGNAL", "GET_SIGNAL reply"},
    {Service::set_signal, "SET_SIGNAL", "SET_SIGNAL reply"},
    {Service::ld_register_application, "LD_REGISTER_APPLICATION", "LD_REGISTER_APPLICATION reply"},
    {Service::set_config, "SET_CONFIG", "SET_CONFIG reply"},
    {Service::get_config, "GET_CONFIG", "GET_CONFIG reply"},
    {Service::set_time_abs, "SET_TIME_ABS", "SET_TIME_ABS reply"},
    {Service::set_time_rel, "SET_TIME_REL", "SET_TIME_REL reply"},
    {Service::get_sync_clock, "GET_SYNC_CLOCK", "GET_SYNC_CLOCK reply"},
    {Service::set_filter, "SET_FILTER", "SET_FILTER reply"},
    {Service::set_function, "SET_FUNCTION", "SET_FUNCTION reply"},
    {Service::get_function, "GET_FUNCTION", "GET_FUNCTION reply"},
    {Service::get_profile, "GET_PROFILE", "GET_PROFILE reply"},
    {Service::cancel_profile, "CANCEL_PROFILE", "CANCEL_PROFILE reply"},
    {Service::do_reset, "DO_RESET", "DO_RESET reply"},
    {Service::trans_idle, "TRANS_IDLE", "TRANS_IDLE reply"},
    {Service::trans_rotate, "TRANS_ROTATE", "TRANS_ROTATE reply"},
    {Service::trans_measure, "TRANS_MEASURE", "TRANS_MEASURE reply"},
    {Service::com_attach, "COM_ATTACH", "COM_ATTACH reply"},
    {Service::com_detach, "COM_DETACH", "COM_DETACH reply"},
    {Service::com_initialize, "COM_INITIALIZE", "COM_INITIALIZE reply"},
    {Service::com_output, "COM_OUTPUT", "COM_OUTPUT reply"},
    {Service::com_data, "COM_DATA", "COM_DATA reply"},
    {Service::file_dir, "DIR", "DIR reply"},
    {Service::file_save, "SAVE", "SAVE reply"},
    {Service::file_load, "LOAD", "LOAD reply"},
    {Service::file_delete, "DELETE", "DELETE reply"},
    {Service::monitor_run, "MONITOR_RUN", "MONITOR_RUN reply"},
    {Service::monitor_profile_log, "MONITOR_PROFILE_LOG", "MONITOR_PROFILE_LOG reply"},
    {Service::service_failure, "SERVICE_FAILURE", "SERVICE_FAILURE reply"},
}};

constexpr std::uint16_t kServiceFailureCode = 0xFF00;

}  // namespace

std::optional<Service> request_service(std::uint16_t code) {
  if (code == kServiceFailureCode) return std::nullopt;
  for (const auto& entry : kServiceNames) {
    if (code_of(entry.service) == code) return entry.service;
  }
  return std::nullopt;
}

bool has_unpublished_layout(Service service) {
  const std::uint16_t group = code_of(service) >> 8;
  return service == Service::ld_register_application || group == 0x06 || group == 0x07 || group == 0x08;
}

bool is_known_code(std::uint16_t code) {
  if (code == kServiceFailureCode) return true;
  return request_service(static_cast<std::uint16_t>(code & ~kResponseBit)).has_value();
}

std::string_view service_name(std::uint16_t code) {
  const bool response = is_response(code) && code != kServiceFailureCode;
  const auto request = static_cast<std::uint16_t>(response ? code & ~kResponseBit : code);
  for (std::size_t i = 0; i < kServiceNames.size(); ++i) {
    if (code_of(kServiceNames[i].service) != request) continue;
    if (kServiceNames[i].service == Service::service_failure && response) break;
    return response ? kServiceNames[i].reply_name : kServiceNames[i].name;
  }
  return "unknown service";
}

std::optional<std::uint16_t> service_code_from_name(std::string_view name) {
  constexpr std::string_view kReplySuffix = " reply";
  bool response = false;
  if (name.size() > kReplySuffix.size() && name.ends_with(kReplySuffix)) {
    response = true;
    name.remove_suffix(kReplySuffix.size());
  }
  for (const auto& entry : kServiceNames) {
    if (entry.name != name) continue;
    if (entry.service == Service::service_failure) {
      if (response) return std::nullopt;
      return kServiceFailureCode;
    }
    return response ? response_code(entry.service) : code_of(entry.service);
  }
  return std::nullopt;
}

}  // namespace ldoem::protocol
