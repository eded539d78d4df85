#include "interrupt.hpp"

#include <algorithm>
#include <thread>

#include <pybind11/pybind11.h>

namespace ldoem::python {

bool python_signal_raised() {
  pybind11::gil_scoped_acquire gil;
  return PyErr_CheckSignals() != 0;
}

bool sliced_sleep(std::chrono::milliseconds pause, InterruptState& state) {
  const auto end = std::chrono::steady_clock::now() + pause;
  while (!state.interrupted) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= end) return true;
    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(end - now, kPollSlice));
    if (python_signal_raised()) state.interrupted = true;
  }
  return false;
}

driver::DriverError InterruptibleTransport::interrupted_error(const char* operation) const {
  return driver::make_error(driver::ErrorKind::interrupted, operation, inner_->name(), "stopped by a Python signal (Ctrl-C)");
}

driver::Status InterruptibleTransport::send(driver::ByteView payload, driver::Deadline deadline) {
  if (state_->interrupted) return driver::fail(interrupted_error("send"));
  return inner_->send(payload, deadline);
}

driver::Expected<driver::Bytes, driver::DriverError> InterruptibleTransport::receive(driver::Deadline deadline) {
  for (;;) {
    if (state_->interrupted) return driver::fail(interrupted_error("receive"));
    const driver::Deadline slice = std::min(deadline, driver::Clock::now() + kPollSlice);
    auto telegram = inner_->receive(slice);
    if (telegram || telegram.error().kind != driver::ErrorKind::timeout || slice >= deadline) return telegram;
    if (python_signal_raised()) state_->interrupted = true;
  }
}

base::SimTime PythonSleeper::now() {
  return std::chrono::duration_cast<base::SimTime>(std::chrono::steady_clock::now().time_since_epoch());
}

void PythonSleeper::sleep_until(base::SimTime time) {
  for (;;) {
    if (state_->interrupted) return;
    const base::SimTime left = time - now();
    if (left <= base::SimTime::zero()) return;
    std::this_thread::sleep_for(std::min<base::SimTime>(left, kPollSlice));
    if (python_signal_raised()) state_->interrupted = true;
  }
}

}  // namespace ldoem::python
