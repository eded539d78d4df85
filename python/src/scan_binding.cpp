// ldoem.scan(): ldoem-scan's acquisition (driver/scan acquire()) from Python, the same plan and
// the same retries, returning the cloud as one (N, 9) float32 array with the PCD file's fields
// x y z intensity t range azimuth tilt ring (docs/point-clouds.md: metres in the pivot frame of
// D5, seconds, radians, ring = layer), in the organised order (HEIGHT rows of WIDTH, row 0 the
// highest tilt, column 0 the leftmost beam; NaN x/y/z/range without an echo). The cloud is
// copied once, straight into the array numpy owns.
#include <cmath>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "convert.hpp"
#include "interrupt.hpp"
#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/scan/acquisition.hpp"
#include "ldoem/scan/scan_options.hpp"
#include "scanner_binding.hpp"

namespace ldoem::python {
namespace {

constexpr py::ssize_t kScanFields = 9;

py::array_t<float> cloud_array(const cloud::PointCloud& cloud) {
  const auto count = static_cast<py::ssize_t>(cloud.size());
  py::array_t<float> out({count, kScanFields});
  float* row = out.mutable_data();
  for (std::size_t index = 0; index < cloud.size(); ++index, row += kScanFields) {
    const cloud::PointRecord point = cloud.record(index);
    row[0] = point.position.x_m;
    row[1] = point.position.y_m;
    row[2] = point.position.z_m;
    row[3] = point.intensity;
    row[4] = point.time_s;
    row[5] = point.range_m;
    row[6] = point.azimuth_rad;
    row[7] = point.tilt_rad;
    row[8] = static_cast<float>(point.ring);
  }
  return out;
}

py::object scan(const std::string& device, std::optional<std::string> lpt, double horizontal_apex_deg,
                double horizontal_resolution_deg, double vertical_apex_deg, double vertical_resolution_deg,
                std::uint16_t speed_hz, bool half_step, double step_rate_hz, double timeout_s, std::uint32_t retries,
                bool info) {
  scan::ScanOptions options;
  options.device = endpoint_or_raise(device, base::EndpointExpect::scanner);
  if (lpt) options.lpt = endpoint_or_raise(*lpt, base::EndpointExpect::lpt);
  options.horizontal_apex_deg = horizontal_apex_deg;
  options.horizontal_resolution_deg = horizontal_resolution_deg;
  options.vertical_apex_deg = vertical_apex_deg;
  options.vertical_resolution_deg = vertical_resolution_deg;
  options.speed_hz = speed_hz;
  options.half_step = half_step;
  options.step_rate_hz = step_rate_hz;
  if (!std::isfinite(timeout_s) || timeout_s <= 0.0 || timeout_s > 1e6) throw py::value_error("timeout must be > 0 s");
  options.timeout = std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(timeout_s * 1000.0)));
  options.retries = retries;
  auto plan = scan::make_plan(options);
  if (!plan) throw py::value_error(plan.error());

  auto state = std::make_shared<InterruptState>();
  driver::ScannerDeviceOptions device_options;
  device_options.scanner.request_timeout = options.timeout;
  device_options.scanner.sleep = [state](std::chrono::milliseconds pause) { sliced_sleep(pause, *state); };
  device_options.stepper.step_rate_hz = options.step_rate_hz;
  const driver::Endpoint scanner_endpoint = *options.device;
  driver::TransportFactory open_transport = [scanner_endpoint, state]()
      -> driver::Expected<std::unique_ptr<driver::TelegramTransport>, driver::DriverError> {
    auto transport = driver::open_transport(scanner_endpoint);
    if (!transport) return driver::fail(transport.error());
    return std::unique_ptr<driver::TelegramTransport>(std::make_unique<InterruptibleTransport>(std::move(*transport), state));
  };
  driver::LptFactory open_lpt;
  if (options.lpt) open_lpt = [endpoint = *options.lpt] { return driver::open_lpt_port(endpoint); };
  driver::ScannerDevice scanner(device, std::move(open_transport), std::move(open_lpt),
                             std::make_unique<PythonSleeper>(state), device_options);
  scan::AcquisitionHooks hooks;
  hooks.should_stop = [state] {
    if (!state->interrupted && python_signal_raised()) state->interrupted = true;
    return state->interrupted.load();
  };
  hooks.sleep = [state](std::chrono::milliseconds pause) { sliced_sleep(pause, *state); };

  base::Expected<scan::Scan, scan::AcquisitionError> result = [&] {
    py::gil_scoped_release release;
    return scan::acquire(scanner, *plan, hooks);
  }();
  if (PyErr_Occurred() != nullptr) throw py::error_already_set();
  if (!result) {
    const scan::AcquisitionError& error = result.error();
    if (error.error) raise_error(*error.error, scan::describe(error));
    raise_error(driver::make_error(driver::ErrorKind::interrupted, error.stage, device), scan::describe(error));
  }
  py::array_t<float> cloud = cloud_array(result->cloud);
  if (!info) return py::object(std::move(cloud));
  py::dict details;
  details["layers_done"] = result->layers_done;
  details["retries_used"] = result->retries_used;
  details["restarts"] = result->restarts;
  details["width"] = result->cloud.layout().width;    // beams per layer
  details["height"] = result->cloud.layout().height;  // layers
  details["status"] = status_dict(result->device.status);
  py::dict identification;
  for (const auto& entry : result->device.identification) identification[py::int_(entry.item)] = entry.text;
  details["identification"] = identification;
  return py::make_tuple(std::move(cloud), details);
}

}  // namespace

void bind_scan(py::module_& m) {
  m.def("scan", &scan, py::arg("device"), py::arg("lpt") = py::none(), py::kw_only(),
        py::arg("horizontal_apex_deg") = 20.0, py::arg("horizontal_resolution_deg") = 0.25,
        py::arg("vertical_apex_deg") = 21.6, py::arg("vertical_resolution_deg") = 0.18, py::arg("speed_hz") = 10,
        py::arg("half_step") = false, py::arg("step_rate_hz") = 200.0, py::arg("timeout") = 5.0,
        py::arg("retries") = scan::kDefaultRetries, py::arg("info") = false,
        "A 3D scan as ldoem-scan takes it: an (N, 9) float32 array x y z intensity t range azimuth tilt ring "
        "(the PCD fields, organised: reshape to (height, width, 9)); with info=True, (array, dict of "
        "layers_done, retries_used, restarts, status, identification, width, height)");
  m.attr("SCAN_FIELDS") = py::make_tuple("x", "y", "z", "intensity", "t", "range", "azimuth", "tilt", "ring");
}

}  // namespace ldoem::python
