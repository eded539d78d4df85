// Responses: typed structs <-> payload bytes (spec 3.2-3.5, D2, D3).
#include <algorithm>

#include "config_codec.hpp"
#include "ldoem/protocol/messages.hpp"
#include "word_reader.hpp"

namespace ldoem::protocol {
namespace {

template <Service S>
constexpr std::uint16_t reply_code(const StatusBlockReply<S>&) { return response_code(S); }
template <Service S>
constexpr std::uint16_t reply_code(const WordReply<S>&) { return response_code(S); }
constexpr std::uint16_t reply_code(const IdentificationReply&) { return response_code(Service::get_identification); }
constexpr std::uint16_t reply_code(const GetStatusReply&) { return response_code(Service::get_status); }
constexpr std::uint16_t reply_code(const GetConfigReply&) { return response_code(Service::get_config); }
constexpr std::uint16_t reply_code(const GetFunctionReply&) { return response_code(Service::get_function); }
constexpr std::uint16_t reply_code(const Profile&) { return response_code(Service::get_profile); }
constexpr std::uint16_t reply_code(const TransMeasureReply&) { return response_code(Service::trans_measure); }
constexpr std::uint16_t reply_code(const ServiceFailure&) { return code_of(Service::service_failure); }

template <Service S>
void append_fields(Bytes& out, const StatusBlockReply<S>& r) { append_status_block(out, r.status); }
template <Service S>
void append_fields(Bytes& out, const WordReply<S>& r) { append_word_be(out, r.value); }
void append_fields(Bytes& out, const IdentificationReply& r) {
  out.insert(out.end(), r.text.begin(), r.text.end());  // D3: no NUL, no padding
}
void append_fields(Bytes& out, const GetStatusReply& r) {
  append_status_block(out, r.status);
  out.insert(out.end(), r.unpublished_fields.begin(), r.unpublished_fields.end());
}
void append_fields(Bytes& out, const GetConfigReply& r) { detail::append_config_body(out, r.body); }
void append_fields(Bytes& out, const GetFunctionReply& r) {
  append_word_be(out, r.sector);
  append_word_be(out, r.function);
  append_word_be(out, r.stop_ticks);
}
void append_fields(Bytes& out, const TransMeasureReply& r) {
  append_status_block(out, r.status);
  append_word_be(out, r.return_code);
}
void append_fields(Bytes& out, const ServiceFailure& r) {
  append_word_be(out, r.request_code);
  append_word_be(out, static_cast<std::uint16_t>(r.reason));
}

using ResponseResult = base::Expected<Response, DecodeError>;

// `rest` is the payload after the code WORD.
template <class Reply>
ResponseResult decode_status_block_reply(ByteView rest) {
  if (rest.size() != StatusBlock::kSizeBytes) return base::Unexpected(DecodeError::bad_length);
  return Response{Reply{read_status_block(rest, 0)}};
}

template <class Reply>
ResponseResult decode_word_reply(ByteView rest) {
  if (rest.size() != 2) return base::Unexpected(DecodeError::bad_length);
  return Response{Reply{read_word_be(rest, 0)}};
}

ResponseResult decode_identification(ByteView rest) {
  // Spec 3.3: text to the end of the payload; stop at a NUL (serial pads odd texts with one).
  const auto end = std::find(rest.begin(), rest.end(), std::uint8_t{0});
  return Response{IdentificationReply{std::string(rest.begin(), end)}};
}

ResponseResult decode_get_status(ByteView rest) {
  if (rest.size() < StatusBlock::kSizeBytes) return base::Unexpected(DecodeError::bad_length);
  GetStatusReply reply;
  reply.status = read_status_block(rest, 0);
  reply.unpublished_fields.assign(rest.begin() + StatusBlock::kSizeBytes, rest.end());
  return Response{std::move(reply)};
}

ResponseResult decode_get_config(ByteView rest) {
  detail::WordReader reader(rest);
  const auto key = reader.try_word();
  if (!key) return base::Unexpected(DecodeError::bad_length);
  auto body = detail::read_config_fields(*key, reader, /*allow_global_zero_pad=*/false);
  if (!body) return base::Unexpected(body.error());
  return Response{GetConfigReply{std::move(*body)}};
}

ResponseResult decode_get_function(ByteView rest) {
  if (rest.size() != 6) return base::Unexpected(DecodeError::bad_length);
  return Response{GetFunctionReply{read_word_be(rest, 0), read_word_be(rest, 2), read_word_be(rest, 4)}};
}

ResponseResult decode_trans_measure(ByteView rest) {
  if (rest.size() != StatusBlock::kSizeBytes + 2) return base::Unexpected(DecodeError::bad_length);
  return Response{TransMeasureReply{read_status_block(rest, 0), read_word_be(rest, 4)}};
}

ResponseResult decode_service_failure(ByteView rest) {
  if (rest.size() != 4) return base::Unexpected(DecodeError::bad_length);
  return Response{ServiceFailure{read_word_be(rest, 0), static_cast<FailureReason>(read_word_be(rest, 2))}};
}

ResponseResult decode_profile_response(ByteView payload) {
  auto profile = decode_profile(payload);
  if (!profile) return base::Unexpected(profile.error());
  return Response{std::move(*profile)};
}

ResponseResult decode_reply_of(Service service, ByteView payload) {
  const ByteView rest = payload.subspan(2);
  switch (service) {
    case Service::get_identification: return decode_identification(rest);
    case Service::get_status: return decode_get_status(rest);
    case Service::get_signal: return decode_word_reply<GetSignalReply>(rest);
    case Service::set_signal: return decode_word_reply<SetSignalReply>(rest);
    case Service::set_config: return decode_word_reply<SetConfigReply>(rest);
    case Service::get_config: return decode_get_config(rest);
    case Service::set_time_abs: return decode_word_reply<SetTimeAbsReply>(rest);
    case Service::set_time_rel: return decode_word_reply<SetTimeRelReply>(rest);
    case Service::get_sync_clock: return decode_word_reply<SyncClockReply>(rest);
    case Service::set_filter: return decode_word_reply<SetFilterReply>(rest);
    case Service::set_function: return decode_word_reply<SetFunctionReply>(rest);
    case Service::get_function: return decode_get_function(rest);
    case Service::get_profile: return decode_profile_response(payload);
    case Service::cancel_profile: return decode_status_block_reply<CancelProfileReply>(rest);
    case Service::do_reset: return decode_word_reply<DoResetReply>(rest);
    case Service::trans_idle: return decode_status_block_reply<TransIdleReply>(rest);
    case Service::trans_rotate: return decode_status_block_reply<TransRotateReply>(rest);
    case Service::trans_measure: return decode_trans_measure(rest);
    default:  // has_unpublished_layout(service); SERVICE_FAILURE replies are decoded before this
      break;
  }
  return base::Unexpected(DecodeError::unknown_service);
}

}  // namespace

std::uint16_t response_code_of(const Response& response) {
  return std::visit([](const auto& r) { return reply_code(r); }, response);
}

Bytes encode_response(const Response& response) {
  if (const auto* profile = std::get_if<Profile>(&response)) return encode_profile(*profile);
  Bytes out;
  append_word_be(out, response_code_of(response));
  std::visit(
      [&out](const auto& r) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(r)>, Profile>) append_fields(out, r);
      },
      response);
  return out;
}

base::Expected<Response, DecodeError> decode_response(ByteView payload) {
  if (payload.size() < 2) return base::Unexpected(DecodeError::truncated);
  const std::uint16_t code = read_word_be(payload, 0);
  if (code == code_of(Service::service_failure)) return decode_service_failure(payload.subspan(2));
  if (!is_response(code)) return base::Unexpected(DecodeError::unknown_service);
  const auto service = request_service(static_cast<std::uint16_t>(code & ~kResponseBit));
  if (!service) return base::Unexpected(DecodeError::unknown_service);
  return decode_reply_of(*service, payload);
}

}  // namespace ldoem::protocol
