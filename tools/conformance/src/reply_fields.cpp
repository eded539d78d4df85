#include "reply_fields.hpp"

#include <cstdio>
#include <map>
#include <type_traits>

#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/service_codes.hpp"
#include "ldoem/protocol/text.hpp"
#include "options.hpp"

namespace ldoem::conformance {
namespace {

namespace p = protocol;

std::string hex_word(std::uint16_t value) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%04X", value);
  return text;
}

std::string hex_bytes(protocol::ByteView bytes) {
  std::string text;
  char pair[4];
  for (std::uint8_t byte : bytes) {
    std::snprintf(pair, sizeof pair, "%02X", byte);
    text += pair;
  }
  return text;
}

struct Collector {
  std::vector<NamedField> fields;
  void add(std::string name, std::string value) { fields.push_back({std::move(name), std::move(value)}); }
  void add(std::string name, std::uint64_t value) { add(std::move(name), std::to_string(value)); }
  void status(const std::string& prefix, const p::StatusBlock& block) {
    add(prefix + ".sensor_mode", static_cast<std::uint64_t>(block.status.sensor));
    add(prefix + ".motor_mode", hex_word(static_cast<std::uint16_t>(block.status.motor)));
    add(prefix + ".reserved", hex_bytes(block.unpublished));
  }
};

// The name of a one-WORD reply's field, by its code.
std::string word_field(std::uint16_t code) {
  switch (code & 0x7FFF) {
    case 0x0104: return "get_signal.port";
    case 0x0105: return "set_signal.result";
    case 0x0201: return "set_config.result";
    case 0x0203: return "set_time_abs.clock_ms";
    case 0x0204: return "set_time_rel.clock_ms";
    case 0x0205: return "get_sync_clock.clock_ms";
    case 0x0209: return "set_filter.item";
    case 0x020A: return "set_function.sector";
    case 0x0401: return "do_reset.level";
    default: return "value";
  }
}

void profile_fields(Collector& out, const p::Profile& profile) {
  out.add("profile.format", hex_word(profile.format));
  out.add("profile.sent", profile.profile_sent);
  out.add("profile.count", profile.profile_count);
  out.add("profile.layer", profile.layer);
  out.add("profile.sectors", profile.sectors.size());
  for (std::size_t s = 0; s < profile.sectors.size(); ++s) {
    const p::SectorBlock& block = profile.sectors[s];
    const std::string prefix = "profile.sector" + std::to_string(s);
    out.add(prefix + ".number", block.sector_num);
    out.add(prefix + ".step", block.dir_step_ticks);
    out.add(prefix + ".points", block.points.size());
    out.add(prefix + ".tstart", block.t_start_ms);
    out.add(prefix + ".startdir", block.start_dir_ticks);
    for (std::size_t i = 0; i < block.points.size(); ++i) {
      const std::string point = prefix + ".point" + std::to_string(i);
      out.add(point + ".distance", block.points[i].distance_q8_m);
      out.add(point + ".direction", block.points[i].direction_ticks);
      out.add(point + ".echo", block.points[i].echo);
    }
    out.add(prefix + ".tend", block.t_end_ms);
    out.add(prefix + ".enddir", block.end_dir_ticks);
  }
  out.status("profile.senstat", profile.status);
}

}  // namespace

std::vector<NamedField> reply_fields(protocol::ByteView payload) {
  Collector out;
  const auto decoded = p::decode_response(payload);
  if (!decoded) {
    out.add("undecodable", hex_bytes(payload));
    return out.fields;
  }
  const std::uint16_t code = p::read_word_be(payload, 0);
  out.add("service", std::string(p::service_name(code)));
  std::visit(
      [&](const auto& reply) {
        using T = std::decay_t<decltype(reply)>;
        if constexpr (std::is_same_v<T, p::IdentificationReply>) {
          out.add("identification.text", reply.text);
        } else if constexpr (std::is_same_v<T, p::GetStatusReply>) {
          out.status("status", reply.status);
          out.add("get_status.extra", hex_bytes(reply.unpublished_fields));
        } else if constexpr (std::is_same_v<T, p::TransMeasureReply>) {
          out.status("status", reply.status);
          out.add("trans_measure.return_code", reply.return_code);
        } else if constexpr (std::is_same_v<T, p::GetConfigReply>) {
          out.add("get_config.key", hex_word(p::read_word_be(payload, 2)));
          for (std::size_t at = 4; at + 1 < payload.size(); at += 2) {
            out.add("get_config.word" + std::to_string((at - 4) / 2), p::read_word_be(payload, at));
          }
        } else if constexpr (std::is_same_v<T, p::GetFunctionReply>) {
          out.add("get_function.sector", reply.sector);
          out.add("get_function.function", reply.function);
          out.add("get_function.stop_ticks", reply.stop_ticks);
        } else if constexpr (std::is_same_v<T, p::ServiceFailure>) {
          out.add("failure.request", hex_word(reply.request_code));
          out.add("failure.reason", static_cast<std::uint64_t>(reply.reason));
        } else if constexpr (std::is_same_v<T, p::Profile>) {
          profile_fields(out, reply);
        } else if constexpr (requires { reply.status; }) {
          out.status("status", reply.status);
        } else if constexpr (requires { reply.value; }) {
          out.add(word_field(code), reply.value);
        }
      },
      *decoded);
  return out.fields;
}

std::vector<FieldDifference> compare_fields(const std::vector<NamedField>& recorded, const std::vector<NamedField>& live,
                                            const std::vector<std::string>& masks) {
  std::map<std::string, const NamedField*> live_by_name;
  for (const auto& field : live) live_by_name.emplace(field.name, &field);
  std::vector<FieldDifference> differences;
  std::map<std::string, bool> seen;
  for (const auto& field : recorded) {
    seen[field.name] = true;
    if (!masks.empty() && matches_any(masks, field.name)) continue;
    const auto other = live_by_name.find(field.name);
    if (other == live_by_name.end()) {
      differences.push_back({field.name, field.value, "(absent)"});
    } else if (other->second->value != field.value) {
      differences.push_back({field.name, field.value, other->second->value});
    }
  }
  for (const auto& field : live) {
    if (seen.count(field.name) || (!masks.empty() && matches_any(masks, field.name))) continue;
    differences.push_back({field.name, "(absent)", field.value});
  }
  return differences;
}

}  // namespace ldoem::conformance
