// Between libldoem's values and Python's: DriverError -> an ldoem.Error exception (its kind,
// message and protocol codes as attributes), status blocks -> dicts, profiles -> numpy
// structured arrays. Every function here needs the GIL.
#pragma once

#include <cstdint>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/error.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::python {

namespace py = pybind11;

// One point of a profile as the numpy record ldoem.PROFILE_DTYPE describes.
struct ProfilePointRecord {
  std::uint16_t sector;
  double angle;  // head angle, degrees in (-180, 180] (D5)
  double range;  // metres; 0 = no echo (D3)
  std::uint16_t echo;
  double time;   // device clock, seconds (T_START..T_END interpolated; NaN without them)
};

// A profile telegram with its points.
struct PythonProfile {
  std::uint16_t format = 0;
  std::uint16_t profile_sent = 0;
  std::uint16_t profile_count = 0;
  std::uint16_t layer = 0;
  std::uint8_t status_byte = 0;
  std::size_t sectors = 0;
  py::array points;
};

// Raises the pending Python exception when a signal handler raised during the call (Ctrl-C),
// else ldoem.Error (or its subclass for the kind) built from `error`.
// `message` replaces describe(error) as the exception's text when given.
[[noreturn]] void raise_error(const driver::DriverError& error, const std::string& message = {});

// A status block as {"status_byte", "sensor", "motor"}.
py::dict status_dict(const protocol::StatusBlock& status);

PythonProfile to_python(const protocol::Profile& profile);

// base::parse_endpoint on the connecting side for `expect` (the scanner: can:, tcp: or serial:;
// the stepper: lpt:), or ValueError with its one-line message (an old spelling names the new one).
driver::Endpoint endpoint_or_raise(const std::string& text, base::EndpointExpect expect);

void register_profile_dtype(py::module_& module);

}  // namespace ldoem::python
