// Requests: typed structs <-> payload bytes (spec 3.2-3.4), with D2's failure reasons.
#include <type_traits>

#include "config_codec.hpp"
#include "ldoem/protocol/messages.hpp"
#include "word_reader.hpp"

namespace ldoem::protocol {

bool ident_item::is_known(std::uint16_t item) {
  switch (item) {
    case kSensorPartNumber: case kSensorName: case kSensorVersion: case kSensorSerialNumber:
    case kEdmSerialNumber: case kFirmwarePartNumber: case kFirmwareName: case kFirmwareVersion:
    case kApplicationPartNumber: case kApplicationName: case kApplicationVersion:
      return true;
    default:
      return false;
  }
}

namespace {

void append_optional_zero(Bytes& out, bool trailing_zero_word) {
  if (trailing_zero_word) append_word_be(out, 0x0000);
}

void append_params(Bytes& out, const GetIdentification& r) { append_word_be(out, r.item); }
void append_params(Bytes& out, const GetStatus& r) { append_optional_zero(out, r.trailing_zero_word); }
void append_params(Bytes& out, const GetSignal& r) { append_optional_zero(out, r.trailing_zero_word); }
void append_params(Bytes& out, const SetSignal& r) { append_word_be(out, r.port_value); }
void append_params(Bytes& out, const SetConfig& r) { detail::append_config_body(out, r.body); }
void append_params(Bytes& out, const GetConfig& r) { append_word_be(out, r.key); }
void append_params(Bytes& out, const SetTimeAbs& r) { append_word_be(out, r.time_ms); }
void append_params(Bytes& out, const SetTimeRel& r) {
  append_word_be(out, static_cast<std::uint16_t>(r.delta_ms));  // two's complement (spec 3.2)
}
void append_params(Bytes& out, const GetSyncClock& r) { append_optional_zero(out, r.trailing_zero_word); }
void append_params(Bytes& out, const SetFilter& r) {
  append_word_be(out, r.item);
  append_word_be(out, r.value);
}
void append_params(Bytes& out, const SetFunction& r) {
  append_word_be(out, r.sector);
  append_word_be(out, r.function);
  append_word_be(out, r.stop_ticks);
  append_word_be(out, r.flash_flag);
}
void append_params(Bytes& out, const GetFunction& r) { append_word_be(out, r.sector); }
void append_params(Bytes& out, const GetProfile& r) {
  append_word_be(out, r.profile_count);
  append_word_be(out, r.format);
}
void append_params(Bytes& out, const CancelProfile& r) { append_optional_zero(out, r.trailing_zero_word); }
void append_params(Bytes& out, const DoReset& r) { append_word_be(out, r.level); }
void append_params(Bytes& out, const TransIdle& r) { append_optional_zero(out, r.trailing_zero_word); }
void append_params(Bytes& out, const TransRotate& r) { append_word_be(out, r.frequency_hz); }
void append_params(Bytes& out, const TransMeasure& r) { append_optional_zero(out, r.trailing_zero_word); }

constexpr Service service_for(const GetIdentification&) { return Service::get_identification; }
constexpr Service service_for(const GetStatus&) { return Service::get_status; }
constexpr Service service_for(const GetSignal&) { return Service::get_signal; }
constexpr Service service_for(const SetSignal&) { return Service::set_signal; }
constexpr Service service_for(const SetConfig&) { return Service::set_config; }
constexpr Service service_for(const GetConfig&) { return Service::get_config; }
constexpr Service service_for(const SetTimeAbs&) { return Service::set_time_abs; }
constexpr Service service_for(const SetTimeRel&) { return Service::set_time_rel; }
constexpr Service service_for(const GetSyncClock&) { return Service::get_sync_clock; }
constexpr Service service_for(const SetFilter&) { return Service::set_filter; }
constexpr Service service_for(const SetFunction&) { return Service::set_function; }
constexpr Service service_for(const GetFunction&) { return Service::get_function; }
constexpr Service service_for(const GetProfile&) { return Service::get_profile; }
constexpr Service service_for(const CancelProfile&) { return Service::cancel_profile; }
constexpr Service service_for(const DoReset&) { return Service::do_reset; }
constexpr Service service_for(const TransIdle&) { return Service::trans_idle; }
constexpr Service service_for(const TransRotate&) { return Service::trans_rotate; }
constexpr Service service_for(const TransMeasure&) { return Service::trans_measure; }

// Decoding context: the request code and the parameter WORDs after it.
struct Params {
  std::uint16_t code;
  detail::WordReader reader;

  base::Unexpected<RequestError> fail(FailureReason reason, DecodeError detail) const {
    return base::Unexpected(RequestError{code, reason, detail});
  }
  base::Unexpected<RequestError> wrong_length() const {
    return fail(FailureReason::wrong_length, DecodeError::bad_length);
  }
  base::Unexpected<RequestError> out_of_range() const {
    return fail(FailureReason::out_of_range, DecodeError::out_of_range);
  }
};

using RequestResult = base::Expected<Request, RequestError>;

// D2: no parameter, or the one trailing 0x0000 WORD serial drivers append.
template <class Parameterless>
RequestResult decode_parameterless(Params& p) {
  switch (p.reader.remaining_words()) {
    case 0:
      return Request{Parameterless{false}};
    case 1:
      if (p.reader.word() == 0x0000) return Request{Parameterless{true}};
      return p.wrong_length();
    default:
      return p.wrong_length();
  }
}

RequestResult decode_get_identification(Params& p) {
  if (p.reader.remaining_words() != 1) return p.wrong_length();
  const std::uint16_t item = p.reader.word();
  if (!ident_item::is_known(item)) return p.out_of_range();
  return Request{GetIdentification{item}};
}

RequestResult decode_set_config(Params& p) {
  if (p.reader.remaining_words() < 1) return p.wrong_length();
  const std::uint16_t key = p.reader.word();
  auto body = detail::read_config_fields(key, p.reader, /*allow_global_zero_pad=*/true);
  if (!body) {
    if (body.error() == DecodeError::unknown_config_key) {
      return p.fail(FailureReason::out_of_range, DecodeError::unknown_config_key);
    }
    return p.wrong_length();
  }
  return Request{SetConfig{std::move(*body)}};
}

RequestResult decode_get_config(Params& p) {
  if (p.reader.remaining_words() != 1) return p.wrong_length();
  const std::uint16_t key = p.reader.word();
  if (!has_config_layout(key)) return p.fail(FailureReason::out_of_range, DecodeError::unknown_config_key);
  return Request{GetConfig{key}};
}

RequestResult decode_set_filter(Params& p) {
  if (p.reader.remaining_words() != 2) return p.wrong_length();
  SetFilter filter{p.reader.word(), p.reader.word()};
  if (filter.item != kFilterItemNearField || filter.value > 1) return p.out_of_range();
  return Request{filter};
}

RequestResult decode_set_function(Params& p) {
  if (p.reader.remaining_words() != 4) return p.wrong_length();
  SetFunction function;
  function.sector = p.reader.word();
  function.function = p.reader.word();
  function.stop_ticks = p.reader.word();
  function.flash_flag = p.reader.word();
  return Request{function};
}

RequestResult decode_get_function(Params& p) {
  if (p.reader.remaining_words() != 1) return p.wrong_length();
  const std::uint16_t sector = p.reader.word();
  if (sector >= kSectorCount) return p.out_of_range();
  return Request{GetFunction{sector}};
}

RequestResult decode_get_profile(Params& p) {
  if (p.reader.remaining_words() != 2) return p.wrong_length();
  GetProfile profile;
  profile.profile_count = p.reader.word();
  profile.format = p.reader.word();
  return Request{profile};
}

RequestResult decode_do_reset(Params& p) {
  if (p.reader.remaining_words() != 1) return p.wrong_length();
  const std::uint16_t level = p.reader.word();
  const bool known = level == reset_level::kFull || level == reset_level::kRestart ||
                     level == reset_level::kHaltToIdle || level == reset_level::kReloadApdVoltage;
  if (!known) return p.out_of_range();
  return Request{DoReset{level}};
}

// One WORD parameter kept raw.
template <class OneWord, class Convert>
RequestResult decode_one_word(Params& p, Convert convert) {
  if (p.reader.remaining_words() != 1) return p.wrong_length();
  return Request{OneWord{convert(p.reader.word())}};
}

const auto kRawWord = [](std::uint16_t word) { return word; };

RequestResult decode_params(Service service, Params& p) {
  switch (service) {
    case Service::get_identification: return decode_get_identification(p);
    case Service::get_status: return decode_parameterless<GetStatus>(p);
    case Service::get_signal: return decode_parameterless<GetSignal>(p);
    case Service::set_signal: return decode_one_word<SetSignal>(p, kRawWord);
    case Service::set_config: return decode_set_config(p);
    case Service::get_config: return decode_get_config(p);
    case Service::set_time_abs: return decode_one_word<SetTimeAbs>(p, kRawWord);
    case Service::set_time_rel:
      return decode_one_word<SetTimeRel>(p, [](std::uint16_t word) { return static_cast<std::int16_t>(word); });
    case Service::get_sync_clock: return decode_parameterless<GetSyncClock>(p);
    case Service::set_filter: return decode_set_filter(p);
    case Service::set_function: return decode_set_function(p);
    case Service::get_function: return decode_get_function(p);
    case Service::get_profile: return decode_get_profile(p);
    case Service::cancel_profile: return decode_parameterless<CancelProfile>(p);
    case Service::do_reset: return decode_do_reset(p);
    case Service::trans_idle: return decode_parameterless<TransIdle>(p);
    case Service::trans_rotate: return decode_one_word<TransRotate>(p, kRawWord);
    case Service::trans_measure: return decode_parameterless<TransMeasure>(p);
    default:  // has_unpublished_layout(service), and SERVICE_FAILURE (no request of its own)
      break;
  }
  return p.fail(FailureReason::unknown_service, DecodeError::unpublished_layout);
}

}  // namespace

Service service_of(const Request& request) {
  return std::visit([](const auto& r) { return service_for(r); }, request);
}

Bytes encode_request(const Request& request) {
  Bytes out;
  append_word_be(out, code_of(service_of(request)));
  std::visit([&out](const auto& r) { append_params(out, r); }, request);
  return out;
}

base::Expected<Request, RequestError> decode_request(ByteView payload) {
  if (payload.size() < 2) {
    return base::Unexpected(RequestError{0x0000, FailureReason::wrong_length, DecodeError::truncated});
  }
  Params params{read_word_be(payload, 0), detail::WordReader(payload, 2)};
  const auto service = request_service(params.code);
  if (!service) return params.fail(FailureReason::unknown_service, DecodeError::unknown_service);
  if (has_unpublished_layout(*service)) {
    return params.fail(FailureReason::unknown_service, DecodeError::unpublished_layout);
  }
  if (payload.size() % 2 != 0) return params.wrong_length();
  return decode_params(*service, params);
}

}  // namespace ldoem::protocol
