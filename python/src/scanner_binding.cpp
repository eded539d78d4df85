#include "scanner_binding.hpp"

#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <pybind11/stl.h>

#include "convert.hpp"
#include "interrupt.hpp"
#include "ldoem/driver/device.hpp"
#include "ldoem/driver/lpt_port.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/driver/tilt_stepper.hpp"

namespace ldoem::python {
namespace {

using std::chrono::milliseconds;

milliseconds to_ms(double seconds, const char* what) {
  if (!std::isfinite(seconds) || seconds <= 0.0 || seconds > 1e6) {
    throw py::value_error(std::string(what) + " must be a number of seconds > 0 and at most 1e6");
  }
  return milliseconds(static_cast<std::int64_t>(std::ceil(seconds * 1000.0)));
}

template <class T>
T take(driver::Expected<T, driver::DriverError>&& result) {
  if (!result) raise_error(result.error());
  return std::move(*result);
}

class PyScanner {
  // Runs `call` without the GIL; a Python signal during it ends it (interrupt.hpp). First in the
  // class: every method's return type is deduced from it.
  template <class Call>
  auto blocking(Call&& call) {
    state_->interrupted = false;
    py::gil_scoped_release release;
    return call();
  }

 public:
  PyScanner(const std::string& endpoint, std::optional<std::string> lpt, double request_timeout_s,
            double rotate_timeout_s, std::uint32_t reconnect_attempts, double reconnect_interval_s, bool connect)
      : state_(std::make_shared<InterruptState>()), endpoint_(endpoint_or_raise(endpoint, base::EndpointExpect::scanner)) {
    if (lpt) {
      lpt_endpoint_ = endpoint_or_raise(*lpt, base::EndpointExpect::lpt);
      if (!std::holds_alternative<driver::LptEndpoint>(*lpt_endpoint_)) throw py::value_error("lpt: expects an lpt: endpoint");
    }
    driver::ScannerOptions options;
    options.request_timeout = to_ms(request_timeout_s, "request_timeout");
    options.rotate_timeout = to_ms(rotate_timeout_s, "rotate_timeout");
    options.reconnect.attempts = reconnect_attempts;
    options.reconnect.interval = to_ms(reconnect_interval_s, "reconnect_interval");
    options.reopen = [endpoint = endpoint_, state = state_] { return open(endpoint, state); };
    options.sleep = [state = state_](milliseconds pause) { sliced_sleep(pause, *state); };
    auto transport = blocking([&] { return open(endpoint_, state_); });
    scanner_ = std::make_unique<driver::Scanner>(take(std::move(transport)), std::move(options));
    if (connect) take(blocking([&] { return scanner_->connect(); }));
  }

  std::string endpoint() const { return driver::format_endpoint(endpoint_); }
  std::string state() const { return std::string(driver::describe(scanner_->state())); }

  py::dict connect() { return status_dict(take(blocking([&] { return scanner_->connect(); })).status); }
  py::dict reconnect() { return status_dict(take(blocking([&] { return scanner_->reconnect(); })).status); }
  // Best effort: a stream is cancelled if the link still takes it; closing never fails (but a
  // Ctrl-C during the cancel is still raised).
  void close() {
    if (scanner_->state() == driver::LifecycleState::active) (void)blocking([&] { return scanner_->cancel_profile(); });
    scanner_->close();
    if (PyErr_Occurred() != nullptr) throw py::error_already_set();
  }
  py::dict status() { return status_dict(take(blocking([&] { return scanner_->get_status(); })).status); }

  py::dict identify() {
    auto entries = take(blocking([&] { return scanner_->identify_all(); }));
    py::dict out;
    for (const auto& entry : entries) out[py::int_(entry.item)] = entry.text;
    return out;
  }

  py::dict global_config() {
    auto config = take(blocking([&] { return scanner_->get_global_config(); }));
    py::dict out;
    out["sensor_id"] = config.sensor_id;
    out["motor_speed_hz"] = config.motor_speed_hz;
    out["angle_step_deg"] = static_cast<double>(config.angle_step_ticks) / base::kTicksPerDegree;
    return out;
  }

  // Reads the global configuration, changes what is given, writes it back (SET_CONFIG, RAM).
  void configure(std::optional<std::uint16_t> motor_speed_hz, std::optional<double> angle_step_deg) {
    auto config = take(blocking([&] { return scanner_->get_global_config(); }));
    if (motor_speed_hz) config.motor_speed_hz = *motor_speed_hz;
    if (angle_step_deg) {
      const double ticks = *angle_step_deg * base::kTicksPerDegree;
      if (!std::isfinite(ticks) || ticks < 1.0 || ticks > 65535.0 || std::fabs(ticks - std::round(ticks)) > 1e-9) {
        throw py::value_error("angle_step_deg must be a positive multiple of 1/16 degree");
      }
      config.angle_step_ticks = static_cast<std::uint16_t>(std::lround(ticks));
    }
    take(blocking([&] { return scanner_->set_config(protocol::ConfigBody(config)); }));
  }

  py::list sectors() {
    auto table = take(blocking([&] { return scanner_->read_sector_table(); }));
    py::list out;
    for (const auto& sector : table) {
      py::dict entry;
      entry["sector"] = sector.sector;
      entry["function"] = sector.function;
      entry["stop_deg"] = static_cast<double>(sector.stop_ticks) / base::kTicksPerDegree;
      out.append(entry);
    }
    return out;
  }

  // [(function, stop_deg), ...]: sector i ends at stop_deg (spec 3.6); temporary unless flash.
  void write_sectors(const std::vector<std::pair<std::uint16_t, double>>& sectors, bool flash) {
    std::vector<driver::SectorDefinition> table;
    for (const auto& [function, stop_deg] : sectors) {
      const double ticks = stop_deg * base::kTicksPerDegree;
      if (!std::isfinite(ticks) || ticks < 0.0 || ticks >= base::kTicksPerTurn) {
        throw py::value_error("stop_deg must be in [0, 360)");
      }
      table.push_back({function, static_cast<std::uint16_t>(std::lround(ticks))});
    }
    take(blocking([&] { return scanner_->write_sector_table(table, flash); }));
  }

  py::dict idle() { return status_dict(take(blocking([&] { return scanner_->trans_idle(); }))); }
  py::dict rotate(std::uint16_t frequency_hz) {
    return status_dict(take(blocking([&] { return scanner_->trans_rotate(frequency_hz); })));
  }
  py::dict measure() { return status_dict(take(blocking([&] { return scanner_->trans_measure(); }))); }
  void reset(std::uint16_t level) { take(blocking([&] { return scanner_->do_reset(level); })); }

  void start_stream(std::uint16_t count, std::uint16_t format) {
    take(blocking([&] { return scanner_->get_profile(count, format); }));
  }
  py::dict stop_stream() { return status_dict(take(blocking([&] { return scanner_->cancel_profile(); }))); }
  PythonProfile next_profile(double timeout_s) {
    const milliseconds timeout = to_ms(timeout_s, "timeout");
    auto profile = take(blocking([&] { return scanner_->next_profile(driver::Clock::now() + timeout); }));
    return to_python(profile);
  }

  py::dict counters() const {
    const auto c = scanner_->counters();
    py::dict out;
    out["requests_sent"] = c.requests_sent;
    out["replies_matched"] = c.replies_matched;
    out["skipped_telegrams"] = c.skipped_telegrams;
    out["profiles_delivered"] = c.profiles_delivered;
    out["profiles_skipped"] = c.profiles_skipped;
    out["reconnects"] = c.reconnects;
    out["stale_replies"] = c.stale_replies;
    return out;
  }

  // Signed steps: positive raises the tilt (D8). Returns the commanded tilt in degrees.
  double move_tilt(std::int64_t steps, bool half_step, double rate_hz) {
    driver::TiltStepper& stepper = tilt_stepper();
    if (steps > driver::kMaxMoveSteps || steps < -static_cast<std::int64_t>(driver::kMaxMoveSteps)) {
      throw py::value_error("steps: at most 20000 per move");
    }
    const auto direction = steps >= 0 ? protocol::TiltDirection::increasing : protocol::TiltDirection::decreasing;
    const auto mode = half_step ? protocol::StepMode::half_step : protocol::StepMode::full_step;
    take(blocking([&] { return stepper.move(static_cast<std::uint32_t>(std::llabs(steps)), direction, mode, rate_hz); }));
    return stepper.tilt_angle_deg();
  }
  double tilt_to(double deg, bool half_step, double rate_hz) {
    driver::TiltStepper& stepper = tilt_stepper();
    const auto mode = half_step ? protocol::StepMode::half_step : protocol::StepMode::full_step;
    take(blocking([&] { return stepper.move_to_angle(deg, mode, rate_hz); }));
    return stepper.tilt_angle_deg();
  }
  double tilt_deg() const { return stepper_ ? stepper_->tilt_angle_deg() : 0.0; }

 private:
  static driver::Expected<std::unique_ptr<driver::TelegramTransport>, driver::DriverError> open(
      const driver::Endpoint& endpoint, const std::shared_ptr<InterruptState>& state) {
    auto transport = driver::open_transport(endpoint);
    if (!transport) return driver::fail(transport.error());
    return std::unique_ptr<driver::TelegramTransport>(std::make_unique<InterruptibleTransport>(std::move(*transport), state));
  }

  driver::TiltStepper& tilt_stepper() {
    if (!lpt_endpoint_) throw py::value_error("this Scanner has no tilt stepper: pass lpt='lpt:...'");
    if (!stepper_) {
      auto port = driver::open_lpt_port(*lpt_endpoint_);
      if (!port) raise_error(port.error());
      lpt_ = std::move(*port);
      sleeper_ = std::make_unique<PythonSleeper>(state_);
      stepper_ = std::make_unique<driver::TiltStepper>(*lpt_, *sleeper_);
    }
    return *stepper_;
  }

  std::shared_ptr<InterruptState> state_;
  driver::Endpoint endpoint_;
  std::unique_ptr<driver::Scanner> scanner_;
  std::optional<driver::Endpoint> lpt_endpoint_;
  std::unique_ptr<driver::LptPort> lpt_;
  std::unique_ptr<PythonSleeper> sleeper_;
  std::unique_ptr<driver::TiltStepper> stepper_;
};

// `for profile in scanner.profiles(...)`: the stream runs from construction; a finite count ends
// the iteration after that many profiles; leaving a `with` block (or close()) cancels it.
class PyProfileStream {
 public:
  PyProfileStream(PyScanner& scanner, std::uint16_t count, std::uint16_t format, double timeout_s)
      : scanner_(scanner), left_(count), endless_(count == 0), timeout_s_(timeout_s) {
    scanner_.start_stream(count, format);
  }
  PythonProfile next() {
    if (!endless_ && left_ == 0) throw py::stop_iteration();
    PythonProfile profile = scanner_.next_profile(timeout_s_);
    if (!endless_) --left_;
    return profile;
  }
  void close() {
    if (scanner_.state() == "active") scanner_.stop_stream();
    left_ = 0;
    endless_ = false;
  }

 private:
  PyScanner& scanner_;
  std::uint32_t left_;
  bool endless_;
  double timeout_s_;
};

}  // namespace

void bind_scanner(py::module_& m) {
  py::class_<PythonProfile>(m, "Profile", "One profile telegram (0x8301): metadata and `points`, a PROFILE_DTYPE array")
      .def_readonly("format", &PythonProfile::format)
      .def_readonly("profile_sent", &PythonProfile::profile_sent)
      .def_readonly("profile_count", &PythonProfile::profile_count)
      .def_readonly("layer", &PythonProfile::layer)
      .def_readonly("status_byte", &PythonProfile::status_byte)
      .def_readonly("sectors", &PythonProfile::sectors)
      .def_readonly("points", &PythonProfile::points)
      .def("__len__", [](const PythonProfile& p) { return p.points.size(); })
      .def("__repr__", [](const PythonProfile& p) {
        return "<ldoem.Profile count=" + std::to_string(p.profile_count) + " points=" + std::to_string(p.points.size()) + ">";
      });

  py::class_<PyProfileStream>(m, "ProfileStream", "An iterator over a profile stream (Scanner.profiles)")
      .def("__iter__", [](PyProfileStream& s) -> PyProfileStream& { return s; })
      .def("__next__", &PyProfileStream::next)
      .def("close", &PyProfileStream::close)
      .def("__enter__", [](PyProfileStream& s) -> PyProfileStream& { return s; })
      // Leaving the block because of an error: that error goes on, not a failing cancel after it
      // (a lost connection fails both); Ctrl-C during the cancel still wins.
      .def("__exit__", [](PyProfileStream& s, const py::object& type, const py::object&, const py::object&) {
        if (type.is_none()) {
          s.close();
          return;
        }
        try {
          s.close();
        } catch (py::error_already_set& failure) {
          if (failure.matches(PyExc_KeyboardInterrupt)) throw;
        }
      });

  py::class_<PyScanner>(m, "Scanner", "An LD-OEM (or ldoem-emud) through libldoem")
      .def(py::init<const std::string&, std::optional<std::string>, double, double, std::uint32_t, double, bool>(),
           py::arg("endpoint"), py::arg("lpt") = py::none(), py::arg("request_timeout") = 5.0,
           py::arg("rotate_timeout") = 10.0, py::arg("reconnect_attempts") = 10, py::arg("reconnect_interval") = 0.5,
           py::arg("connect") = true)
      .def_property_readonly("endpoint", &PyScanner::endpoint)
      .def_property_readonly("state", &PyScanner::state)
      .def_property_readonly("tilt_deg", &PyScanner::tilt_deg)
      .def("connect", &PyScanner::connect)
      .def("reconnect", &PyScanner::reconnect)
      .def("close", &PyScanner::close)
      .def("__enter__", [](PyScanner& s) -> PyScanner& { return s; })
      .def("__exit__", [](PyScanner& s, py::args) { s.close(); })
      .def("status", &PyScanner::status)
      .def("identify", &PyScanner::identify)
      .def("global_config", &PyScanner::global_config)
      .def("configure", &PyScanner::configure, py::arg("motor_speed_hz") = py::none(), py::arg("angle_step_deg") = py::none())
      .def("sectors", &PyScanner::sectors)
      .def("write_sectors", &PyScanner::write_sectors, py::arg("sectors"), py::arg("flash") = false)
      .def("idle", &PyScanner::idle)
      .def("rotate", &PyScanner::rotate, py::arg("frequency_hz") = 0)
      .def("measure", &PyScanner::measure)
      .def("reset", &PyScanner::reset, py::arg("level"))
      .def("start_stream", &PyScanner::start_stream, py::arg("count") = 0, py::arg("format") = protocol::kFormatRangeEcho)
      .def("stop_stream", &PyScanner::stop_stream)
      .def("next_profile", &PyScanner::next_profile, py::arg("timeout") = 5.0)
      .def(
          "profiles",
          [](PyScanner& s, std::uint16_t count, std::uint16_t format, double timeout) {
            return std::make_unique<PyProfileStream>(s, count, format, timeout);
          },
          py::arg("count") = 0, py::arg("format") = protocol::kFormatRangeEcho, py::arg("timeout") = 5.0,
          py::keep_alive<0, 1>())
      .def("counters", &PyScanner::counters)
      .def("move_tilt", &PyScanner::move_tilt, py::arg("steps"), py::arg("half_step") = false, py::arg("rate_hz") = 200.0)
      .def("tilt_to", &PyScanner::tilt_to, py::arg("deg"), py::arg("half_step") = false, py::arg("rate_hz") = 200.0);

  m.attr("FORMAT_RANGE") = protocol::kFormatRange;
  m.attr("FORMAT_RANGE_ECHO") = protocol::kFormatRangeEcho;
}

}  // namespace ldoem::python
