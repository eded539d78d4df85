// The one error type of libldoem. Callers branch on `kind` (and is_retryable), never on the
// text that describe() makes for logs (design.md conventions 2 and 5).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::driver {

using base::Expected;
using base::Unexpected;

enum class ErrorKind : std::uint8_t {
  // Retryable: the same call may succeed later (recovery_for says how: retry, or reconnect first).
  timeout,      // no reply / no connection / no frame before the deadline (spec 6): a dropped reply
  busy,         // the resource is held elsewhere or a queue is full (EAGAIN, EBUSY, ENOBUFS)
  interrupted,  // a signal cut the call short (EINTR)
  framing,            // the bytes on the wire broke the framing (spec 4.1 / 4.2 / D1)
  corrupted_reply,    // a telegram with our reply code that does not decode: cut short or damaged
  connection_closed,  // the peer closed or reset the connection, or the line hung up: reconnect
  // Final: retrying the same call the same way will not help.
  service_failure,    // the device answered SERVICE_FAILURE (D2) naming our request (reason 5,
                      // our request arrived corrupted, is retryable)
  device_fault,       // the device reports a fault in its status (motor nibble, sensor ERROR):
                      // final until DO_RESET level 2 after the cause is gone (D11)
  unexpected_reply,   // a well-formed reply that does not match the request (echo, layout)
  refused,            // the device refused in-band (TRANS_MEASURE 1..4, SET_CONFIG != 0, FF FF ...)
  system,             // any other failing syscall (errno in system_errno)
  unsupported,        // the host lacks a feature (e.g. no CAN_ISOTP in the kernel)
  invalid_argument,   // the caller passed a value the driver cannot use
  wrong_state,        // the Scanner lifecycle forbids the call (see lifecycle.hpp)
};

std::string_view describe(ErrorKind kind);

struct DriverError {
  ErrorKind kind = ErrorKind::system;
  std::string operation;  // what was attempted: "connect", "GET_STATUS", "PPCLAIM", ...
  std::string object;     // what it was attempted on: "tcp:127.0.0.1:49152", "/dev/parport0"
  int system_errno = 0;   // for system / busy / interrupted / connection_closed, when known
  std::uint16_t request_code = 0;  // the service we waited for (0 outside the Scanner)
  std::optional<protocol::FailureReason> failure_reason;  // service_failure: D2 reason
  std::uint16_t in_band_code = 0;  // refused: the device's code (TRANS_MEASURE 1..4, ...)
  std::optional<protocol::DecodeError> decode_detail;  // framing / corrupted_reply / unexpected_reply
  std::optional<std::uint8_t> device_status;  // device_fault: the status byte (spec 2.4)
  std::string detail;  // extra words for describe(); never parsed

  bool operator==(const DriverError&) const = default;
};

// What a caller does about an error (docs/faults.md, "Host side"):
enum class Recovery : std::uint8_t {
  retry,         // send the same request again (after the device had time: a short back-off)
  reconnect,     // open the transport again (Scanner::reconnect), then repeat the request
  reset_device,  // final for this job: the device is faulted; DO_RESET level 2 once the cause
                 // is gone (a stall that ended, a fault cleared), then start again
  none,          // final: fix the call, the configuration or the host
};

Recovery recovery_for(const DriverError& error);
std::string_view describe(Recovery recovery);

// True for timeout, busy, interrupted, framing, corrupted_reply and connection_closed (the last
// after a reconnect).
bool is_retryable(ErrorKind kind);
// recovery_for(error) is retry or reconnect: is_retryable(kind), or SERVICE_FAILURE reason 5.
bool is_retryable(const DriverError& error);

// The fault a status block reports, as a device_fault error; nothing for a healthy status
// (motor nibble 0 and a sensor mode other than ERROR).
std::optional<DriverError> device_fault_in(const protocol::StatusBlock& status, std::string operation,
                                           std::string object);

// One line, e.g. "GET_STATUS tcp:127.0.0.1:49152: timeout: no reply within 5000 ms" or
// "TRANS_MEASURE can:vcan0: refused by the device: code 2 (mean pulse frequency too high)".
std::string describe(const DriverError& error);

// A DriverError for a failed syscall: EAGAIN/EWOULDBLOCK/EBUSY/ENOBUFS -> busy,
// EINTR -> interrupted, EPIPE/ECONNRESET -> connection_closed, anything else -> system.
DriverError system_error(std::string operation, std::string object, int errno_value);

DriverError make_error(ErrorKind kind, std::string operation, std::string object, std::string detail = {});

// A call that yields nothing but may fail.
using Status = Expected<std::monostate, DriverError>;
inline Status ok() { return std::monostate{}; }
inline Unexpected<DriverError> fail(DriverError error) { return Unexpected<DriverError>(std::move(error)); }

}  // namespace ldoem::driver
