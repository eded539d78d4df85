// Error kinds as wire tokens and the typed reply fields (status, tilt, profile, identification)
// of the hub's line protocol; the request and reply grammar itself is in hub_protocol.cpp.
#include <cstdio>

#include "hub_text.hpp"
#include "ldoem/hub/hub_protocol.hpp"
#include "ldoem/protocol/messages.hpp"

namespace ldoem::hub {

namespace text {

std::string hex_of(protocol::ByteView bytes) {
  std::string text;
  text.reserve(bytes.size() * 2);
  for (std::uint8_t byte : bytes) {
    text.push_back(hex_digit(byte >> 4));
    text.push_back(hex_digit(byte));
  }
  return text;
}

std::optional<protocol::Bytes> bytes_of_hex(std::string_view text) {
  if (text.size() % 2 != 0) {
    return std::nullopt;
  }
  protocol::Bytes bytes;
  bytes.reserve(text.size() / 2);
  for (std::size_t i = 0; i < text.size(); i += 2) {
    const auto byte = parse_integer<std::uint8_t>(text.substr(i, 2), 16);
    if (!byte) {
      return std::nullopt;
    }
    bytes.push_back(*byte);
  }
  return bytes;
}

}  // namespace text

namespace {

using text::bytes_of_hex;
using text::format_double;
using text::hex_of;
using text::parse_integer;

std::string_view sensor_mode_token(protocol::SensorMode mode) {
  switch (mode) {
    case protocol::SensorMode::idle: return "idle";
    case protocol::SensorMode::rotate: return "rotate";
    case protocol::SensorMode::measure: return "measure";
    case protocol::SensorMode::error: return "error";
  }
  return "unknown";
}

}  // namespace

std::string_view error_kind_token(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::timeout: return "timeout";
    case ErrorKind::busy: return "busy";
    case ErrorKind::interrupted: return "interrupted";
    case ErrorKind::framing: return "framing";
    case ErrorKind::corrupted_reply: return "corrupted_reply";
    case ErrorKind::device_fault: return "device_fault";
    case ErrorKind::connection_closed: return "connection_closed";
    case ErrorKind::service_failure: return "service_failure";
    case ErrorKind::unexpected_reply: return "unexpected_reply";
    case ErrorKind::refused: return "refused";
    case ErrorKind::system: return "system";
    case ErrorKind::unsupported: return "unsupported";
    case ErrorKind::invalid_argument: return "invalid_argument";
    case ErrorKind::wrong_state: return "wrong_state";
  }
  return "system";
}

ErrorKind error_kind_from_token(std::string_view token) {
  constexpr ErrorKind kAll[] = {ErrorKind::timeout,         ErrorKind::busy,
                                ErrorKind::interrupted,     ErrorKind::framing,
                                ErrorKind::connection_closed, ErrorKind::service_failure,
                                ErrorKind::unexpected_reply, ErrorKind::refused,
                                ErrorKind::system,          ErrorKind::unsupported,
                                ErrorKind::invalid_argument, ErrorKind::wrong_state,
                                ErrorKind::corrupted_reply, ErrorKind::device_fault};
  for (ErrorKind kind : kAll) {
    if (error_kind_token(kind) == token) {
      return kind;
    }
  }
  return ErrorKind::invalid_argument;
}

std::string_view recovery_token(driver::Recovery recovery) {
  switch (recovery) {
    case driver::Recovery::retry: return "retry";
    case driver::Recovery::reconnect: return "reconnect";
    case driver::Recovery::reset_device: return "reset_device";
    case driver::Recovery::none: return "none";
  }
  return "none";
}

std::vector<ReplyField> status_fields(const StatusBlock& status) {
  protocol::Bytes block;
  protocol::append_status_block(block, status);
  return {{"status", hex_of(block)},
          {"mode", std::string(sensor_mode_token(status.status.sensor))},
          {"motor", std::string(protocol::motor_mode_name(status.status.motor))}};
}

std::optional<StatusBlock> status_from(const HubReply& reply) {
  const auto text = reply.field("status");
  if (!text) {
    return std::nullopt;
  }
  const auto bytes = bytes_of_hex(*text);
  if (!bytes || bytes->size() != StatusBlock::kSizeBytes) {
    return std::nullopt;
  }
  return protocol::read_status_block(*bytes, 0);
}

std::vector<ReplyField> tilt_fields(const TiltPosition& tilt) {
  return {{"tilt_half_steps", std::to_string(tilt.half_steps)}, {"tilt_deg", format_double(tilt.tilt_deg())}};
}

std::optional<TiltPosition> tilt_from(const HubReply& reply) {
  const auto text = reply.field("tilt_half_steps");
  if (!text) {
    return std::nullopt;
  }
  const auto half_steps = parse_integer<std::int64_t>(*text);
  if (!half_steps) {
    return std::nullopt;
  }
  return TiltPosition{*half_steps};
}

std::vector<ReplyField> profile_fields(const ProfileSample& sample) {
  std::vector<ReplyField> fields = tilt_fields(sample.tilt);
  fields.emplace_back("profile", hex_of(protocol::encode_profile(sample.profile)));
  return fields;
}

std::optional<ProfileSample> profile_from(const HubReply& reply) {
  const auto tilt = tilt_from(reply);
  const auto text = reply.field("profile");
  if (!tilt || !text) {
    return std::nullopt;
  }
  const auto payload = bytes_of_hex(*text);
  if (!payload) {
    return std::nullopt;
  }
  auto profile = protocol::decode_profile(*payload);
  if (!profile) {
    return std::nullopt;
  }
  return ProfileSample{std::move(profile.value()), *tilt};
}

std::vector<ReplyField> info_fields(const DeviceInfo& info) {
  std::vector<ReplyField> fields = status_fields(info.status);
  for (const auto& entry : info.identification) {
    char key[16];
    std::snprintf(key, sizeof key, "ident.%04X", static_cast<unsigned>(entry.item));
    fields.emplace_back(key, entry.text);
  }
  return fields;
}

std::optional<DeviceInfo> info_from(const HubReply& reply) {
  const auto status = status_from(reply);
  if (!status) {
    return std::nullopt;
  }
  DeviceInfo info{*status, {}};
  constexpr std::string_view kPrefix = "ident.";
  for (const auto& [key, value] : reply.fields) {
    if (key.starts_with(kPrefix)) {
      const auto item = parse_integer<std::uint16_t>(std::string_view(key).substr(kPrefix.size()), 16);
      if (!item) {
        return std::nullopt;
      }
      info.identification.push_back({*item, value});
    }
  }
  return info;
}

}  // namespace ldoem::hub
