// Blocking libldoem calls from Python: the GIL is released for the call, and the waits inside it
// are cut into slices of at most kPollSlice, between which Python's signal handlers run (with the
// GIL). A handler that raises (Ctrl-C: KeyboardInterrupt) ends the call with
// ErrorKind::interrupted; the binding then sees the pending Python exception and raises it. So
// Ctrl-C stops a read within a slice, and every wait still ends at its own deadline.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>

#include "ldoem/driver/tilt_stepper.hpp"
#include "ldoem/driver/transport.hpp"

namespace ldoem::python {

inline constexpr std::chrono::milliseconds kPollSlice{50};

// Set once a Python signal handler raised during the current call; cleared when a call starts.
struct InterruptState {
  std::atomic<bool> interrupted{false};
};

// Takes the GIL and runs the signal handlers: true when one raised (the exception stays set).
bool python_signal_raised();

// Waits `pause` in slices; returns false (early) once a handler raised.
bool sliced_sleep(std::chrono::milliseconds pause, InterruptState& state);

class InterruptibleTransport final : public driver::TelegramTransport {
 public:
  InterruptibleTransport(std::unique_ptr<driver::TelegramTransport> inner, std::shared_ptr<InterruptState> state)
      : inner_(std::move(inner)), state_(std::move(state)) {}
  driver::Status send(driver::ByteView payload, driver::Deadline deadline) override;
  driver::Expected<driver::Bytes, driver::DriverError> receive(driver::Deadline deadline) override;
  std::vector<driver::Bytes> take_arrived(std::size_t limit) override { return inner_->take_arrived(limit); }
  void close() override { inner_->close(); }
  const std::string& name() const override { return inner_->name(); }
  driver::TransportCounters counters() const override { return inner_->counters(); }

 private:
  driver::DriverError interrupted_error(const char* operation) const;
  std::unique_ptr<driver::TelegramTransport> inner_;
  std::shared_ptr<InterruptState> state_;
};

// The tilt stepper's pacing on CLOCK_MONOTONIC, sleeping in slices so that Ctrl-C stops a move
// at its next step (TiltStepper then answers ErrorKind::interrupted).
class PythonSleeper final : public driver::Sleeper {
 public:
  explicit PythonSleeper(std::shared_ptr<InterruptState> state) : state_(std::move(state)) {}
  base::SimTime now() override;
  void sleep_until(base::SimTime time) override;
  void interrupt() override { state_->interrupted = true; }
  bool interrupted() const override { return state_->interrupted; }

 private:
  std::shared_ptr<InterruptState> state_;
};

}  // namespace ldoem::python
