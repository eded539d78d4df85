#include "convert.hpp"

#include <cmath>
#include <limits>

#include "ldoem/protocol/service_codes.hpp"
#include "ldoem/scan/profile_points.hpp"


namespace ldoem::python {
namespace {

const char* kind_name(driver::ErrorKind kind) {
  switch (kind) {
    case driver::ErrorKind::timeout: return "timeout";
    case driver::ErrorKind::busy: return "busy";
    case driver::ErrorKind::interrupted: return "interrupted";
    case driver::ErrorKind::framing: return "framing";
    case driver::ErrorKind::corrupted_reply: return "corrupted_reply";
    case driver::ErrorKind::connection_closed: return "connection_closed";
    case driver::ErrorKind::service_failure: return "service_failure";
    case driver::ErrorKind::device_fault: return "device_fault";
    case driver::ErrorKind::unexpected_reply: return "unexpected_reply";
    case driver::ErrorKind::refused: return "refused";
    case driver::ErrorKind::system: return "system";
    case driver::ErrorKind::unsupported: return "unsupported";
    case driver::ErrorKind::invalid_argument: return "invalid_argument";
    case driver::ErrorKind::wrong_state: return "wrong_state";
  }
  return "system";
}

// The names of docs/faults.md's "Host side" (describe(Recovery) is a sentence for logs).
const char* recovery_name(driver::Recovery recovery) {
  switch (recovery) {
    case driver::Recovery::retry: return "retry";
    case driver::Recovery::reconnect: return "reconnect";
    case driver::Recovery::reset_device: return "reset_device";
    case driver::Recovery::none: return "none";
  }
  return "none";
}

const char* sensor_name(protocol::SensorMode mode) {
  switch (mode) {
    case protocol::SensorMode::idle: return "IDLE";
    case protocol::SensorMode::rotate: return "ROTATE";
    case protocol::SensorMode::measure: return "MEASURE";
    case protocol::SensorMode::error: return "ERROR";
  }
  return "UNKNOWN";
}

}  // namespace

void raise_error(const driver::DriverError& error, const std::string& message) {
  if (PyErr_Occurred() != nullptr) throw py::error_already_set();
  py::dict fields;
  fields["kind"] = kind_name(error.kind);
  fields["operation"] = error.operation;
  fields["object"] = error.object;
  fields["errno"] = error.system_errno;
  fields["request_code"] = error.request_code;
  fields["request"] = error.request_code != 0 ? py::object(py::str(std::string(protocol::service_name(error.request_code))))
                                              : py::object(py::none());
  fields["failure_reason"] = error.failure_reason ? py::object(py::int_(static_cast<int>(*error.failure_reason)))
                                                  : py::object(py::none());
  fields["in_band_code"] = error.in_band_code;
  fields["device_status"] = error.device_status ? py::object(py::int_(*error.device_status)) : py::object(py::none());
  fields["detail"] = error.detail;
  fields["retryable"] = driver::is_retryable(error);
  fields["recovery"] = recovery_name(driver::recovery_for(error));
  py::object exception = py::module_::import("ldoem._errors").attr("from_driver")(message.empty() ? driver::describe(error) : message, fields);
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exception.ptr())), exception.ptr());
  throw py::error_already_set();
}

py::dict status_dict(const protocol::StatusBlock& status) {
  py::dict out;
  out["status_byte"] = status.status.to_byte();
  out["sensor"] = sensor_name(status.status.sensor);
  out["motor"] = std::string(protocol::motor_mode_name(status.status.motor));
  return out;
}

PythonProfile to_python(const protocol::Profile& profile) {
  PythonProfile out;
  out.format = profile.format;
  out.profile_sent = profile.profile_sent;
  out.profile_count = profile.profile_count;
  out.layer = profile.layer;
  out.status_byte = profile.status.status.to_byte();
  out.sectors = profile.sectors.size();
  std::size_t total = 0;
  for (const auto& sector : profile.sectors) total += sector.points.size();
  py::array_t<ProfilePointRecord> points(static_cast<py::ssize_t>(total));
  auto* record = points.mutable_data();
  const bool has_direction = (profile.format & protocol::profile_bits::kDirection) != 0;
  const bool has_times = (profile.format & protocol::profile_bits::kTStart) != 0 &&
                         (profile.format & protocol::profile_bits::kTEnd) != 0;
  for (const auto& sector : profile.sectors) {
    const std::size_t count = sector.points.size();
    // The device clock is a WORD of ms (spec 3.5): T_END may have wrapped past T_START.
    const double span_ms = static_cast<double>(static_cast<std::uint16_t>(sector.t_end_ms - sector.t_start_ms));
    for (std::size_t index = 0; index < count; ++index) {
      const auto& point = sector.points[index];
      record->sector = sector.sector_num;
      record->angle = scan::beam_angle_deg(sector, index, has_direction);
      record->range = static_cast<double>(point.distance_q8_m) / 256.0;
      record->echo = point.echo;
      const double share = count > 1 ? static_cast<double>(index) / static_cast<double>(count - 1) : 0.0;
      record->time = has_times ? (static_cast<double>(sector.t_start_ms) + span_ms * share) / 1000.0
                               : std::numeric_limits<double>::quiet_NaN();
      ++record;
    }
  }
  out.points = std::move(points);
  return out;
}

driver::Endpoint endpoint_or_raise(const std::string& text, base::EndpointExpect expect) {
  // The grammar of every tool, connecting side (docs/endpoints.md).
  auto endpoint = base::parse_endpoint(text, base::EndpointUse{base::EndpointSide::connect, expect});
  if (!endpoint) throw py::value_error(driver::describe(endpoint.error()));
  return *endpoint;
}

void register_profile_dtype(py::module_& module) {
  PYBIND11_NUMPY_DTYPE(ProfilePointRecord, sector, angle, range, echo, time);
  module.attr("PROFILE_DTYPE") = py::dtype::of<ProfilePointRecord>();
}

}  // namespace ldoem::python
