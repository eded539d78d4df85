#include "ldoem/faults/fault_spec.hpp"

#include <cctype>
#include <cmath>
#include <sstream>

#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::faults {
namespace {

constexpr double kTicksPerDegree = 16.0;      // spec 3.6: angles in 1/16 deg
constexpr double kMaxSeconds = kMaxFaultSeconds;  // about 11.5 days: longer is a typo
constexpr double kMaxCount = 1.0e12;

FieldError error(FieldErrorKind kind, std::string_view key, std::string detail) {
  return FieldError{kind, std::string(key), std::move(detail)};
}

std::optional<FieldError> as_number(std::string_view key, const FieldValue& value, double& out) {
  if (const auto* number = std::get_if<double>(&value)) {
    if (!std::isfinite(*number)) return error(FieldErrorKind::out_of_range, key, "must be finite");
    out = *number;
    return std::nullopt;
  }
  return error(FieldErrorKind::wrong_type, key, "must be a number");
}

std::optional<FieldError> as_text(std::string_view key, const FieldValue& value, std::string& out) {
  if (const auto* text = std::get_if<std::string>(&value)) {
    out = *text;
    return std::nullopt;
  }
  return error(FieldErrorKind::wrong_type, key, "must be text");
}

std::optional<FieldError> as_seconds(std::string_view key, const FieldValue& value, SimTime& out,
                                     bool allow_zero) {
  double seconds = 0.0;
  if (auto problem = as_number(key, value, seconds)) return problem;
  if (seconds < 0.0 || (!allow_zero && seconds == 0.0)) {
    return error(FieldErrorKind::out_of_range, key, allow_zero ? "must be >= 0" : "must be > 0");
  }
  if (seconds > kMaxSeconds) return error(FieldErrorKind::out_of_range, key, "must be at most 1e6 s");
  out = std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(seconds));
  return std::nullopt;
}

std::optional<FieldError> as_count(std::string_view key, const FieldValue& value, std::uint64_t min,
                                   std::uint64_t& out) {
  double number = 0.0;
  if (auto problem = as_number(key, value, number)) return problem;
  if (number != std::floor(number)) return error(FieldErrorKind::wrong_type, key, "must be an integer");
  if (number < static_cast<double>(min) || number > kMaxCount) {
    return error(FieldErrorKind::out_of_range, key,
                 "must be an integer in [" + std::to_string(min) + ", 1e12]");
  }
  out = static_cast<std::uint64_t>(number);
  return std::nullopt;
}

std::optional<FieldError> as_service(std::string_view key, const FieldValue& value, std::uint16_t& out) {
  std::string name;
  if (auto problem = as_text(key, value, name)) return problem;
  for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const auto code = protocol::service_code_from_name(name);
  if (!code || protocol::is_response(*code) || !protocol::request_service(*code)) {
    return error(FieldErrorKind::unknown_service, key,
                 "unknown service '" + std::get<std::string>(value) + "' (a request name of spec 3.2, e.g. GET_PROFILE)");
  }
  out = *code;
  return std::nullopt;
}

std::optional<FieldError> as_degrees(std::string_view key, const FieldValue& value, std::uint16_t& out) {
  double degrees = 0.0;
  if (auto problem = as_number(key, value, degrees)) return problem;
  if (degrees < 0.0 || degrees > 360.0) return error(FieldErrorKind::out_of_range, key, "must be in [0, 360]");
  out = static_cast<std::uint16_t>(std::lround(degrees * kTicksPerDegree));
  return std::nullopt;
}

std::optional<FieldError> as_u32(std::string_view key, const FieldValue& value, std::uint64_t min,
                                 std::uint32_t& out, std::uint32_t max = UINT32_MAX) {
  std::uint64_t number = 0;
  if (auto problem = as_count(key, value, min, number)) return problem;
  if (number > max) {
    return error(FieldErrorKind::out_of_range, key,
                 "must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  }
  out = static_cast<std::uint32_t>(number);
  return std::nullopt;
}

}  // namespace

std::optional<FieldError> FaultEntryBuilder::set_trigger(std::string_view key, const FieldValue& value) {
  if (key == "at_s") {
    ++triggers_;
    TriggerAt at;
    if (auto problem = as_seconds(key, value, at.at, true)) return problem;
    spec_.trigger = at;
    return std::nullopt;
  }
  if (key == "probability") {
    ++triggers_;
    TriggerProbability draw;
    if (auto problem = as_number(key, value, draw.probability)) return problem;
    if (draw.probability < 0.0 || draw.probability > 1.0) {
      return error(FieldErrorKind::out_of_range, key, "must be in [0, 1]");
    }
    spec_.trigger = draw;
    return std::nullopt;
  }
  const bool on = key.starts_with("on.");
  if (on || key.starts_with("every.")) {
    // The map counts as one trigger however many members it has.
    bool& first_member = on ? has_on_service_ : has_every_service_;
    bool& second_member = on ? has_on_nth_ : has_every_count_;
    if (!first_member && !second_member) {
      ++triggers_;
      if (on) spec_.trigger = TriggerOnNth{};
      else spec_.trigger = TriggerEvery{};
    }
    const std::string_view member = key.substr(on ? 3 : 6);
    if (on && !std::holds_alternative<TriggerOnNth>(spec_.trigger)) return std::nullopt;  // counted above
    if (!on && !std::holds_alternative<TriggerEvery>(spec_.trigger)) return std::nullopt;
    if (member == "service") {
      first_member = true;
      std::uint16_t code = 0;
      if (auto problem = as_service(key, value, code)) return problem;
      if (on) std::get<TriggerOnNth>(spec_.trigger).service = code;
      else std::get<TriggerEvery>(spec_.trigger).service = code;
      return std::nullopt;
    }
    if (member == (on ? "nth" : "count")) {
      second_member = true;
      std::uint64_t number = 0;
      if (auto problem = as_count(key, value, 1, number)) return problem;
      if (on) std::get<TriggerOnNth>(spec_.trigger).nth = number;
      else std::get<TriggerEvery>(spec_.trigger).count = number;
      return std::nullopt;
    }
    return error(FieldErrorKind::unknown_key, key,
                 on ? "unknown key (on: has service and nth)" : "unknown key (every: has service and count)");
  }
  return error(FieldErrorKind::unknown_key, key, "unknown key");
}

std::optional<FieldError> FaultEntryBuilder::set(std::string_view key, const FieldValue& value) {
  if (key == "kind") {
    has_kind_ = true;
    std::string name;
    if (auto problem = as_text(key, value, name)) return problem;
    const auto kind = fault_kind_from_name(name);
    if (!kind) {
      return error(FieldErrorKind::unknown_kind, key,
                   "unknown fault kind '" + name + "' (D11: " + std::string(all_fault_names()) + ")");
    }
    spec_.kind = *kind;
    return std::nullopt;
  }
  if (key == "duration_s") {
    has_duration_ = true;
    SimTime duration{};
    if (auto problem = as_seconds(key, value, duration, false)) return problem;
    spec_.duration = duration;
    return std::nullopt;
  }
  if (key == "count") {
    has_count_ = true;
    std::uint64_t count = 0;
    if (auto problem = as_count(key, value, 1, count)) return problem;
    spec_.count = count;
    return std::nullopt;
  }
  if (key == "transport") {
    std::string name;
    if (auto problem = as_text(key, value, name)) return problem;
    if (name == "any") {
      spec_.transport.reset();
      return std::nullopt;
    }
    const auto transport = protocol::transport_from_name(name);
    if (!transport) return error(FieldErrorKind::out_of_range, key, "must be tcp, serial, can, lpt or any");
    spec_.transport = *transport;
    return std::nullopt;
  }
  if (key == "service") {
    std::uint16_t code = 0;
    if (auto problem = as_service(key, value, code)) return problem;
    spec_.service = code;
    return std::nullopt;
  }
  if (key == "from_deg" || key == "to_deg") {
    params_.emplace_back(std::string(key), FaultParam::sector_range);
    std::uint16_t ticks = 0;
    if (auto problem = as_degrees(key, value, ticks)) return problem;
    (key == "from_deg" ? spec_.from_ticks : spec_.to_ticks) = ticks;
    return std::nullopt;
  }
  if (key == "fraction") {
    params_.emplace_back(std::string(key), FaultParam::fraction);
    double fraction = 0.0;
    if (auto problem = as_number(key, value, fraction)) return problem;
    if (fraction < 0.0 || fraction > 1.0) return error(FieldErrorKind::out_of_range, key, "must be in [0, 1]");
    spec_.fraction = fraction;
    return std::nullopt;
  }
  if (key == "delay_s") {
    params_.emplace_back(std::string(key), FaultParam::delay_s);
    if (auto problem = as_seconds(key, value, spec_.delay, true)) return problem;
    if (spec_.delay > std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(kMaxDelaySeconds))) {
      return error(FieldErrorKind::out_of_range, key, "must be at most 60 s");
    }
    return std::nullopt;
  }
  if (key == "off_s") {
    params_.emplace_back(std::string(key), FaultParam::off_s);
    return as_seconds(key, value, spec_.off, true);
  }
  if (key == "bytes_kept") {
    params_.emplace_back(std::string(key), FaultParam::bytes_kept);
    return as_u32(key, value, 0, spec_.bytes_kept);
  }
  if (key == "bytes") {
    params_.emplace_back(std::string(key), FaultParam::bytes);
    return as_u32(key, value, 1, spec_.garbage_bytes, kMaxGarbageBytes);
  }
  if (key == "bytes_per_s") {
    params_.emplace_back(std::string(key), FaultParam::bytes_per_s);
    return as_u32(key, value, 1, spec_.bytes_per_s, kMaxBytesPerSecond);
  }
  return set_trigger(key, value);
}

std::variant<FaultSpec, FieldError> FaultEntryBuilder::finish() const {
  if (!has_kind_) return error(FieldErrorKind::missing_key, "kind", "is required (a D11 fault name)");
  if (triggers_ > 1) {
    return error(FieldErrorKind::conflicting_keys, "",
                 "give at most one trigger: at_s, on, every or probability");
  }
  if (has_on_service_ != has_on_nth_ && std::holds_alternative<TriggerOnNth>(spec_.trigger)) {
    return error(FieldErrorKind::missing_key, has_on_service_ ? "on.nth" : "on.service", "is required");
  }
  if (has_every_service_ != has_every_count_ && std::holds_alternative<TriggerEvery>(spec_.trigger)) {
    return error(FieldErrorKind::missing_key, has_every_service_ ? "every.count" : "every.service",
                 "is required");
  }
  if (has_duration_ && has_count_) {
    return error(FieldErrorKind::conflicting_keys, "count", "give either duration_s or count, not both");
  }
  for (const auto& [key, param] : params_) {
    if (!accepts(spec_.kind, param)) {
      return error(FieldErrorKind::unknown_key, key,
                   "not a parameter of " + std::string(fault_name(spec_.kind)));
    }
  }
  const FaultKindInfo& kind = info(spec_.kind);
  if (spec_.transport) {
    if (kind.fault_class == FaultClass::device) {
      return error(FieldErrorKind::conflicting_keys, "transport",
                   std::string(kind.name) + " is a device fault: it has no transport");
    }
    if (!applies_to(spec_.kind, *spec_.transport)) {
      return error(FieldErrorKind::conflicting_keys, "transport",
                   std::string(kind.name) + " does not apply to " + std::string(protocol::transport_name(*spec_.transport)));
    }
  }
  if (spec_.service && kind.fault_class == FaultClass::device) {
    return error(FieldErrorKind::conflicting_keys, "service",
                 std::string(kind.name) + " is a device fault: it has no service filter");
  }
  if (spec_.kind == FaultKind::blind) {
    const bool sector = spec_.from_ticks || spec_.to_ticks;
    if (sector && !(spec_.from_ticks && spec_.to_ticks)) {
      return error(FieldErrorKind::missing_key, spec_.from_ticks ? "to_deg" : "from_deg", "is required");
    }
    if (sector == spec_.fraction.has_value()) {
      return error(FieldErrorKind::conflicting_keys, "", "blind needs either from_deg/to_deg or fraction");
    }
  }
  if (spec_.kind == FaultKind::window_dirt && !spec_.fraction) {
    return error(FieldErrorKind::missing_key, "fraction", "is required for window_dirt");
  }
  if (kind.extent == FaultExtent::one_shot && (has_duration_ || has_count_)) {
    return error(FieldErrorKind::conflicting_keys, has_duration_ ? "duration_s" : "count",
                 std::string(kind.name) + " acts once: it has no duration or count");
  }
  return spec_;
}

std::string describe(const FaultSpec& spec) {
  std::ostringstream out;
  out << fault_name(spec.kind);
  auto seconds = [](SimTime t) { return std::chrono::duration<double>(t).count(); };
  if (const auto* at = std::get_if<TriggerAt>(&spec.trigger)) out << " at_s=" << seconds(at->at);
  if (const auto* on = std::get_if<TriggerOnNth>(&spec.trigger)) {
    out << " on=" << protocol::service_name(on->service) << "#" << on->nth;
  }
  if (const auto* every = std::get_if<TriggerEvery>(&spec.trigger)) {
    out << " every=" << protocol::service_name(every->service) << "/" << every->count;
  }
  if (const auto* draw = std::get_if<TriggerProbability>(&spec.trigger)) out << " probability=" << draw->probability;
  if (spec.duration) out << " duration_s=" << seconds(*spec.duration);
  if (spec.count) out << " count=" << *spec.count;
  if (spec.transport) out << " transport=" << protocol::transport_name(*spec.transport);
  if (spec.service) out << " service=" << protocol::service_name(*spec.service);
  if (spec.from_ticks) out << " from_deg=" << *spec.from_ticks / kTicksPerDegree;
  if (spec.to_ticks) out << " to_deg=" << *spec.to_ticks / kTicksPerDegree;
  if (spec.fraction) out << " fraction=" << *spec.fraction;
  if (accepts(spec.kind, FaultParam::delay_s)) out << " delay_s=" << seconds(spec.delay);
  if (accepts(spec.kind, FaultParam::bytes_kept)) out << " bytes_kept=" << spec.bytes_kept;
  if (accepts(spec.kind, FaultParam::bytes)) out << " bytes=" << spec.garbage_bytes;
  if (accepts(spec.kind, FaultParam::bytes_per_s)) out << " bytes_per_s=" << spec.bytes_per_s;
  if (accepts(spec.kind, FaultParam::off_s)) out << " off_s=" << seconds(spec.off);
  return out.str();
}

}  // namespace ldoem::faults
