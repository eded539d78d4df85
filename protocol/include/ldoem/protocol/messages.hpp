// Typed requests and responses of every service whose layout is published (spec 3.2-3.5),
// their encoders, and decoders that report exactly what D2 needs to answer a bad request.
//
// Values are kept raw: decode_request checks only syntax (lengths, and the closed value sets
// that no state can make valid, listed at decode_request). Whether a value is acceptable now
// (state, speed 5..20, sector table) is the emulator's decision.
#pragma once

#include <cstdint>
#include <string>
#include <variant>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/config.hpp"
#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/service_codes.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::protocol {

// ---------------------------------------------------------------------------------- requests
// `trailing_zero_word` on a parameterless request: S2 appends one 0x0000 WORD, which D2
// accepts; it is kept so that the telegram re-encodes byte for byte.

// IDENTITEM values (spec 3.3).
namespace ident_item {
inline constexpr std::uint16_t kSensorPartNumber = 0x0000;
inline constexpr std::uint16_t kSensorName = 0x0001;
inline constexpr std::uint16_t kSensorVersion = 0x0002;
inline constexpr std::uint16_t kSensorSerialNumber = 0x0003;
inline constexpr std::uint16_t kEdmSerialNumber = 0x0004;
inline constexpr std::uint16_t kFirmwarePartNumber = 0x0010;
inline constexpr std::uint16_t kFirmwareName = 0x0011;
inline constexpr std::uint16_t kFirmwareVersion = 0x0012;
inline constexpr std::uint16_t kApplicationPartNumber = 0x0020;
inline constexpr std::uint16_t kApplicationName = 0x0021;
inline constexpr std::uint16_t kApplicationVersion = 0x0022;
bool is_known(std::uint16_t item);
}  // namespace ident_item

// DO_RESET levels (spec 3.3).
namespace reset_level {
inline constexpr std::uint16_t kFull = 0x0000;
inline constexpr std::uint16_t kRestart = 0x0001;
inline constexpr std::uint16_t kHaltToIdle = 0x0002;
inline constexpr std::uint16_t kReloadApdVoltage = 0x0010;
}  // namespace reset_level

// SET_FILTER (spec 3.3): only near-field suppression is known.
inline constexpr std::uint16_t kFilterItemNearField = 0x0001;

// Sector functions (spec 3.6).
namespace sector_function {
inline constexpr std::uint16_t kNotInitialised = 0;
inline constexpr std::uint16_t kNoMeasurement = 1;
inline constexpr std::uint16_t kReserved = 2;
inline constexpr std::uint16_t kNormalMeasurement = 3;
inline constexpr std::uint16_t kReferenceMeasurement = 4;
}  // namespace sector_function
inline constexpr std::uint16_t kSectorCount = 8;

struct GetIdentification { std::uint16_t item = 0; bool operator==(const GetIdentification&) const = default; };
struct GetStatus { bool trailing_zero_word = false; bool operator==(const GetStatus&) const = default; };
struct GetSignal { bool trailing_zero_word = false; bool operator==(const GetSignal&) const = default; };
struct SetSignal { std::uint16_t port_value = 0; bool operator==(const SetSignal&) const = default; };
struct SetConfig { ConfigBody body; bool operator==(const SetConfig&) const = default; };
struct GetConfig { std::uint16_t key = 0; bool operator==(const GetConfig&) const = default; };
struct SetTimeAbs { std::uint16_t time_ms = 0; bool operator==(const SetTimeAbs&) const = default; };
struct SetTimeRel { std::int16_t delta_ms = 0; bool operator==(const SetTimeRel&) const = default; };
struct GetSyncClock { bool trailing_zero_word = false; bool operator==(const GetSyncClock&) const = default; };
struct SetFilter {
  std::uint16_t item = kFilterItemNearField;
  std::uint16_t value = 0;  // 0 off, 1 on
  bool operator==(const SetFilter&) const = default;
};
struct SetFunction {
  std::uint16_t sector = 0;  // 0..7 (checked by the emulator: in-band FF FF, D2)
  std::uint16_t function = 0;
  std::uint16_t stop_ticks = 0;
  std::uint16_t flash_flag = 0;  // 1 = write to flash, anything else temporary
  bool operator==(const SetFunction&) const = default;
};
struct GetFunction { std::uint16_t sector = 0; bool operator==(const GetFunction&) const = default; };
struct GetProfile {
  std::uint16_t profile_count = 0;  // 0 = stream until CANCEL_PROFILE
  std::uint16_t format = kFormatRange;
  bool operator==(const GetProfile&) const = default;
};
struct CancelProfile { bool trailing_zero_word = false; bool operator==(const CancelProfile&) const = default; };
struct DoReset { std::uint16_t level = reset_level::kHaltToIdle; bool operator==(const DoReset&) const = default; };
struct TransIdle { bool trailing_zero_word = false; bool operator==(const TransIdle&) const = default; };
struct TransRotate {
  std::uint16_t frequency_hz = 0;  // 0 = configured speed, 1..4 reserved, 5..20 Hz
  bool operator==(const TransRotate&) const = default;
};
struct TransMeasure { bool trailing_zero_word = false; bool operator==(const TransMeasure&) const = default; };

using Request = std::variant<GetIdentification, GetStatus, GetSignal, SetSignal, SetConfig, GetConfig,
                             SetTimeAbs, SetTimeRel, GetSyncClock, SetFilter, SetFunction, GetFunction,
                             GetProfile, CancelProfile, DoReset, TransIdle, TransRotate, TransMeasure>;

Service service_of(const Request& request);

// Why decode_request refused a payload, in the form D2 answers: SERVICE_FAILURE
// `FF 00 | request_code | reason`. request_code is 0 when the payload is too short to hold one.
// For SET_CONFIG and SET_FUNCTION, D2 prefers the service's in-band error; the emulator picks
// that from request_code.
struct RequestError {
  std::uint16_t request_code = 0;
  FailureReason reason = FailureReason::wrong_length;
  DecodeError detail = DecodeError::truncated;
  bool operator==(const RequestError&) const = default;
};

Bytes encode_request(const Request& request);

// Syntax checks made here (reason out_of_range): GET_IDENTIFICATION item not in spec 3.3,
// GET_FUNCTION sector > 7, SET_FILTER item != 1 or value > 1, DO_RESET level not 0/1/2/0x10,
// GET_CONFIG / SET_CONFIG key without a layout. Wrong lengths give reason wrong_length, with
// the one trailing 0x0000 WORD accepted on parameterless requests and on SET_CONFIG global (D2).
base::Expected<Request, RequestError> decode_request(ByteView payload);

// --------------------------------------------------------------------------------- responses

struct IdentificationReply {
  std::string text;  // D3: sent without NUL or padding; decoding stops at the first NUL
  bool operator==(const IdentificationReply&) const = default;
};

// GET_STATUS reply: the status block, then fields nobody published (kept raw, empty from us).
struct GetStatusReply {
  StatusBlock status;
  Bytes unpublished_fields;
  bool operator==(const GetStatusReply&) const = default;
};

// Replies that carry only a status block after the code (spec 3.2).
template <Service kService>
struct StatusBlockReply {
  StatusBlock status;
  bool operator==(const StatusBlockReply&) const = default;
};
using CancelProfileReply = StatusBlockReply<Service::cancel_profile>;
using TransIdleReply = StatusBlockReply<Service::trans_idle>;
using TransRotateReply = StatusBlockReply<Service::trans_rotate>;

// TRANS_MEASURE return codes (spec 3.3).
namespace measure_return {
inline constexpr std::uint16_t kOk = 0;
inline constexpr std::uint16_t kMaxPulseFrequencyTooHigh = 1;
inline constexpr std::uint16_t kMeanPulseFrequencyTooHigh = 2;
inline constexpr std::uint16_t kSectorBordersNotConfigured = 3;
inline constexpr std::uint16_t kSectorBordersNotMultipleOfStep = 4;
}  // namespace measure_return

struct TransMeasureReply {
  StatusBlock status;
  std::uint16_t return_code = measure_return::kOk;
  bool operator==(const TransMeasureReply&) const = default;
};

// Replies that carry one WORD after the code.
template <Service kService>
struct WordReply {
  std::uint16_t value = 0;
  bool operator==(const WordReply&) const = default;
};
using GetSignalReply = WordReply<Service::get_signal>;         // PORTVAL
using SetSignalReply = WordReply<Service::set_signal>;         // D3: 0x0000 = accepted
using SetConfigReply = WordReply<Service::set_config>;         // 0x0000 success, 0x0001 refused (D2)
using SetTimeAbsReply = WordReply<Service::set_time_abs>;      // new clock value, ms
using SetTimeRelReply = WordReply<Service::set_time_rel>;      // new clock value, ms
using SyncClockReply = WordReply<Service::get_sync_clock>;     // clock value, ms
using SetFilterReply = WordReply<Service::set_filter>;         // FILTERITEM echo
using SetFunctionReply = WordReply<Service::set_function>;     // D3: SECTORNUM, or kSetFunctionInvalid
using DoResetReply = WordReply<Service::do_reset>;             // RESETLEVEL echo

inline constexpr std::uint16_t kSetConfigSuccess = 0x0000;
inline constexpr std::uint16_t kSetConfigRefused = 0x0001;  // D2
inline constexpr std::uint16_t kSetFunctionInvalid = 0xFFFF;  // spec 3.3

struct GetConfigReply {
  ConfigBody body;  // the key is echoed first; decoding picks the layout by it
  bool operator==(const GetConfigReply&) const = default;
};

struct GetFunctionReply {
  std::uint16_t sector = 0;
  std::uint16_t function = 0;
  std::uint16_t stop_ticks = 0;
  bool operator==(const GetFunctionReply&) const = default;
};

// D2: `FF 00 | REQUEST_CODE(W) | REASON(W)`.
struct ServiceFailure {
  std::uint16_t request_code = 0;
  FailureReason reason = FailureReason::unknown_service;
  bool operator==(const ServiceFailure&) const = default;
};

constexpr ServiceFailure failure_reply(const RequestError& error) {
  return ServiceFailure{error.request_code, error.reason};
}

using Response = std::variant<IdentificationReply, GetStatusReply, GetSignalReply, SetSignalReply,
                              SetConfigReply, GetConfigReply, SetTimeAbsReply, SetTimeRelReply,
                              SyncClockReply, SetFilterReply, SetFunctionReply, GetFunctionReply,
                              Profile, CancelProfileReply, DoResetReply, TransIdleReply,
                              TransRotateReply, TransMeasureReply, ServiceFailure>;

// The response code the alternative is sent with (0x8xxx, or 0xFF00).
std::uint16_t response_code_of(const Response& response);

Bytes encode_response(const Response& response);

// Decodes any reply the LD sends, including profile telegrams (0x8301) and SERVICE_FAILURE.
// A request code (bit 15 clear) or a code of spec 3.2 without a reply layout is
// unknown_service; a length that does not fit the layout is bad_length.
base::Expected<Response, DecodeError> decode_response(ByteView payload);

}  // namespace ldoem::protocol
