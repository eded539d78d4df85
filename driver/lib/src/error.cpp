#include "ldoem/driver/error.hpp"

#include <cerrno>
#include <cstring>

#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::driver {

std::string_view describe(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::timeout: return "timeout";
    case ErrorKind::busy: return "busy";
    case ErrorKind::interrupted: return "interrupted";
    case ErrorKind::framing: return "framing error";
    case ErrorKind::corrupted_reply: return "corrupted reply";
    case ErrorKind::device_fault: return "device fault";
    case ErrorKind::connection_closed: return "connection closed";
    case ErrorKind::service_failure: return "SERVICE_FAILURE from the device";
    case ErrorKind::unexpected_reply: return "unexpected reply";
    case ErrorKind::refused: return "refused by the device";
    case ErrorKind::system: return "system error";
    case ErrorKind::unsupported: return "unsupported";
    case ErrorKind::invalid_argument: return "invalid argument";
    case ErrorKind::wrong_state: return "not allowed in this state";
  }
  return "unknown error";
}

namespace {

// What a kind of error asks of the caller, before any detail of the error is known.
Recovery recovery_of_kind(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::timeout:
    case ErrorKind::busy:
    case ErrorKind::interrupted:
    case ErrorKind::framing:
    case ErrorKind::corrupted_reply:
      return Recovery::retry;
    case ErrorKind::connection_closed:
      return Recovery::reconnect;
    case ErrorKind::device_fault:
      return Recovery::reset_device;
    case ErrorKind::service_failure:
    case ErrorKind::unexpected_reply:
    case ErrorKind::refused:
    case ErrorKind::system:
    case ErrorKind::unsupported:
    case ErrorKind::invalid_argument:
    case ErrorKind::wrong_state:
      return Recovery::none;
  }
  return Recovery::none;
}

}  // namespace

bool is_retryable(ErrorKind kind) {
  const Recovery recovery = recovery_of_kind(kind);
  return recovery == Recovery::retry || recovery == Recovery::reconnect;
}

Recovery recovery_for(const DriverError& error) {
  // Reason 5: the device saw our frame broken on the way (D2), the request itself is fine.
  if (error.kind == ErrorKind::service_failure && error.failure_reason == protocol::FailureReason::framing) {
    return Recovery::retry;
  }
  return recovery_of_kind(error.kind);
}

std::string_view describe(Recovery recovery) {
  switch (recovery) {
    case Recovery::retry: return "retryable";
    case Recovery::reconnect: return "retryable after a reconnect";
    case Recovery::reset_device: return "final until the device is reset";
    case Recovery::none: return "final";
  }
  return "final";
}

bool is_retryable(const DriverError& error) {
  const Recovery recovery = recovery_for(error);
  return recovery == Recovery::retry || recovery == Recovery::reconnect;
}

namespace {

std::string_view motor_words(protocol::MotorMode motor) {
  switch (motor) {
    case protocol::MotorMode::ok: return "ok";
    case protocol::MotorMode::spin_too_low: return "spin too low";
    case protocol::MotorMode::spin_too_high: return "spin too high";
    case protocol::MotorMode::fault: return "motor fault";
  }
  return "unlisted motor nibble";
}

std::string hex_byte(std::uint8_t byte) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  return std::string("0x") + kDigits[byte >> 4] + kDigits[byte & 0xF];
}

}  // namespace

std::optional<DriverError> device_fault_in(const protocol::StatusBlock& status, std::string operation,
                                           std::string object) {
  const protocol::StatusByte byte = status.status;
  const bool in_error = byte.sensor == protocol::SensorMode::error;
  if (byte.motor == protocol::MotorMode::ok && !in_error) {
    return std::nullopt;
  }
  std::string detail = "status " + hex_byte(byte.to_byte()) + " (motor nibble " +
                       hex_byte(static_cast<std::uint8_t>(byte.motor)) + ": " +
                       std::string(motor_words(byte.motor)) + (in_error ? ", sensor mode ERROR)" : ")");
  DriverError error = make_error(ErrorKind::device_fault, std::move(operation), std::move(object), std::move(detail));
  error.device_status = byte.to_byte();
  return error;
}

namespace {

std::string hex_word(std::uint16_t word) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string text = "0x0000";
  for (int i = 0; i < 4; ++i) {
    text[static_cast<std::size_t>(5 - i)] = kDigits[(word >> (4 * i)) & 0xF];
  }
  return text;
}

void append_specifics(std::string& line, const DriverError& error) {
  if (error.kind == ErrorKind::service_failure) {
    line += ": request ";
    line += hex_word(error.request_code);
    if (error.failure_reason) {
      line += ", reason ";
      line += hex_word(static_cast<std::uint16_t>(*error.failure_reason));
      line += " (";
      line += protocol::describe(*error.failure_reason);
      line += ")";
    }
  }
  if (error.kind == ErrorKind::refused) {
    line += ": code ";
    line += std::to_string(error.in_band_code);
  }
  if (error.decode_detail) {
    line += ": ";
    line += protocol::describe(*error.decode_detail);
  }
  if (!error.detail.empty()) {
    line += ": ";
    line += error.detail;
  }
  if (error.system_errno != 0) {
    line += ": ";
    line += std::strerror(error.system_errno);
  }
}

}  // namespace

std::string describe(const DriverError& error) {
  std::string line = error.operation.empty() ? std::string("driver") : error.operation;
  if (!error.object.empty()) {
    line += " ";
    line += error.object;
  }
  line += ": ";
  line += describe(error.kind);
  append_specifics(line, error);
  for (char& c : line) {
    if (c == '\n' || c == '\r') {
      c = ' ';  // one line, whatever a detail string holds
    }
  }
  return line;
}

DriverError system_error(std::string operation, std::string object, int errno_value) {
  ErrorKind kind = ErrorKind::system;
  if (errno_value == EAGAIN || errno_value == EWOULDBLOCK || errno_value == EBUSY ||
      errno_value == ENOBUFS) {
    kind = ErrorKind::busy;
  } else if (errno_value == EINTR) {
    kind = ErrorKind::interrupted;
  } else if (errno_value == EPIPE || errno_value == ECONNRESET) {
    kind = ErrorKind::connection_closed;
  }
  DriverError error = make_error(kind, std::move(operation), std::move(object));
  error.system_errno = errno_value;
  return error;
}

DriverError make_error(ErrorKind kind, std::string operation, std::string object, std::string detail) {
  DriverError error;
  error.kind = kind;
  error.operation = std::move(operation);
  error.object = std::move(object);
  error.detail = std::move(detail);
  return error;
}

}  // namespace ldoem::driver
