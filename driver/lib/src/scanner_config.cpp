// The Scanner's configuration services (GET/SET_CONFIG, the clock, SET_FILTER and the sector
// table), apart from the lifecycle and streaming in scanner.cpp so that each file stays readable.
#include "ldoem/driver/scanner.hpp"

#include <string>
#include <utility>

#include "ldoem/protocol/service_codes.hpp"
#include "scanner_call.hpp"

namespace ldoem::driver {

namespace p = protocol;

// ------------------------------------------------------------------ configuration group

Expected<p::ConfigBody, DriverError> Scanner::get_config(p::ConfigKey key) {
  const auto key_word = static_cast<std::uint16_t>(key);
  auto reply = call<p::GetConfigReply>(p::GetConfig{key_word}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  if (p::key_of(reply->body) != key) {
    return fail(error_for(ErrorKind::unexpected_reply, p::code_of(p::Service::get_config),
                          "the reply echoes another key"));
  }
  return std::move(reply->body);
}

template <class Body>
Expected<Body, DriverError> Scanner::get_config_as() {
  auto body = get_config(Body::kKey);
  if (!body) {
    return fail(body.error());
  }
  return std::get<Body>(*body);  // get_config checked the key, which picks the alternative
}

Expected<p::GlobalConfig, DriverError> Scanner::get_global_config() { return get_config_as<p::GlobalConfig>(); }
Expected<p::EthernetConfig, DriverError> Scanner::get_ethernet_config() { return get_config_as<p::EthernetConfig>(); }
Expected<p::SerialConfig, DriverError> Scanner::get_serial_config() { return get_config_as<p::SerialConfig>(); }
Expected<p::CanConfig, DriverError> Scanner::get_can_config() { return get_config_as<p::CanConfig>(); }
Expected<p::InterlaceConfig, DriverError> Scanner::get_interlace_config() { return get_config_as<p::InterlaceConfig>(); }

Status Scanner::set_config(const p::ConfigBody& body) {
  auto reply = call<p::SetConfigReply>(p::SetConfig{body}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  if (reply->value != p::kSetConfigSuccess) {
    DriverError error = error_for(ErrorKind::refused, p::code_of(p::Service::set_config));
    error.in_band_code = reply->value;
    return fail(std::move(error));
  }
  return ok();
}

Expected<std::uint16_t, DriverError> Scanner::set_time_abs(std::uint16_t time_ms) {
  auto reply = call<p::SetTimeAbsReply>(p::SetTimeAbs{time_ms}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  return reply->value;
}

Expected<std::uint16_t, DriverError> Scanner::set_time_rel(std::int16_t delta_ms) {
  auto reply = call<p::SetTimeRelReply>(p::SetTimeRel{delta_ms}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  return reply->value;
}

Expected<std::uint16_t, DriverError> Scanner::get_sync_clock() {
  auto reply = call<p::SyncClockReply>(p::GetSyncClock{}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  return reply->value;
}

Status Scanner::set_filter(bool near_field_suppression) {
  const p::SetFilter request{p::kFilterItemNearField, static_cast<std::uint16_t>(near_field_suppression ? 1 : 0)};
  auto reply = call<p::SetFilterReply>(request, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  if (reply->value != p::kFilterItemNearField) {
    return fail(error_for(ErrorKind::unexpected_reply, p::code_of(p::Service::set_filter),
                          "the reply echoes another filter item"));
  }
  return ok();
}

Expected<p::GetFunctionReply, DriverError> Scanner::get_function(std::uint16_t sector) {
  auto reply = call<p::GetFunctionReply>(p::GetFunction{sector}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  if (reply->sector != sector) {
    return fail(error_for(ErrorKind::unexpected_reply, p::code_of(p::Service::get_function),
                          "the reply names sector " + std::to_string(reply->sector)));
  }
  return reply;
}

Status Scanner::set_function(const p::SetFunction& sector) {
  auto reply = call<p::SetFunctionReply>(sector, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  if (reply->value == p::kSetFunctionInvalid) {
    DriverError error = error_for(ErrorKind::refused, p::code_of(p::Service::set_function));
    error.in_band_code = reply->value;
    return fail(std::move(error));
  }
  return ok();
}

Expected<std::vector<p::GetFunctionReply>, DriverError> Scanner::read_sector_table() {
  std::vector<p::GetFunctionReply> table;
  for (std::uint16_t sector = 0; sector < p::kSectorCount; ++sector) {
    auto entry = get_function(sector);
    if (!entry) {
      return fail(entry.error());
    }
    table.push_back(*entry);
    if (entry->function == p::sector_function::kNotInitialised) {
      break;  // spec 3.6: function 0 ends the table
    }
  }
  return table;
}

Status Scanner::write_sector_table(std::span<const SectorDefinition> sectors, bool to_flash) {
  if (sectors.size() > p::kSectorCount) {
    return fail(error_for(ErrorKind::invalid_argument, p::code_of(p::Service::set_function),
                          "at most 8 sectors (spec 3.6)"));
  }
  const std::uint16_t flash_flag = to_flash ? 1 : 0;
  for (std::size_t i = 0; i < sectors.size(); ++i) {
    auto written = set_function(p::SetFunction{static_cast<std::uint16_t>(i), sectors[i].function,
                                               sectors[i].stop_ticks, flash_flag});
    if (!written) {
      return written;
    }
  }
  if (sectors.size() < p::kSectorCount) {
    return set_function(p::SetFunction{static_cast<std::uint16_t>(sectors.size()),
                                       p::sector_function::kNotInitialised, 0, flash_flag});
  }
  return ok();
}

}  // namespace ldoem::driver
