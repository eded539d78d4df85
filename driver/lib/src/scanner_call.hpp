// Scanner::call, the one request-reply exchange every service uses, as a template both
// scanner.cpp and scanner_config.cpp instantiate.
#pragma once

#include <utility>
#include <variant>

#include "ldoem/driver/scanner.hpp"
#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::driver {

template <class Reply>
Expected<Reply, DriverError> Scanner::call(const protocol::Request& request, std::chrono::milliseconds timeout,
                                           bool allow_unconfigured) {
  const std::uint16_t code = protocol::code_of(protocol::service_of(request));
  auto payload = exchange(request, timeout, allow_unconfigured);
  if (!payload) {
    return fail(payload.error());
  }
  auto decoded = protocol::decode_response(*payload);
  if (!decoded) {
    // Our code with a body that does not decode: the telegram was cut short or damaged on the
    // way (D11 truncate_reply); asking again may well get it whole.
    DriverError error = error_for(ErrorKind::corrupted_reply, code, "reply does not decode");
    error.decode_detail = decoded.error();
    return fail(std::move(error));
  }
  auto* reply = std::get_if<Reply>(&*decoded);
  if (reply == nullptr) {
    return fail(error_for(ErrorKind::unexpected_reply, code, "reply of another layout"));
  }
  return std::move(*reply);
}

}  // namespace ldoem::driver
