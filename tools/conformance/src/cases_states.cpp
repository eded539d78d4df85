// states/: every request the state table of spec 5 (with D2's entries) forbids, answered
// with D2 reason 3 or the service's in-band error, the state left unchanged; every transition
// to the current state answered with the current status; and what is allowed everywhere.
#include <optional>

#include "case_steps.hpp"
#include "cases.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;

enum class Start : std::uint8_t { idle, rotate, measure };

std::string_view start_name(Start start) {
  switch (start) {
    case Start::idle: return "IDLE";
    case Start::rotate: return "ROTATE";
    case Start::measure: return "MEASURE";
  }
  return "?";
}

SensorMode mode_of(Start start) {
  switch (start) {
    case Start::idle: return SensorMode::idle;
    case Start::rotate: return SensorMode::rotate;
    case Start::measure: return SensorMode::measure;
  }
  return SensorMode::error;
}

void enter(Session& session, Start start) {
  if (start == Start::idle) return;  // the baseline is IDLE
  session.enter_rotate();
  if (start == Start::measure) session.enter_measure();
}

void expect_state(Session& session, Start start) {
  session.expect("GET_STATUS afterwards (" + std::string(start_name(start)) + ")", encode_request(GetStatus{}),
                 BytePattern::exactly(reply_bytes(GetStatusReply{status(mode_of(start)), {}})));
}

// The request is answered `reply` and the state stays `start`.
Case refused(std::string request_name, Start start, Bytes request, Bytes reply) {
  std::string name = "states/" + request_name + "_in_" + std::string(start_name(start));
  return Case{std::move(name),
              [start, request = std::move(request), reply = std::move(reply)](Session& session) {
                enter(session, start);
                session.expect("refusal", request, BytePattern::exactly(reply));
                expect_state(session, start);
              },
              true, true, {}};
}

Case wrong_state(std::string request_name, Start start, const Request& request) {
  const Bytes payload = encode_request(request);
  return refused(std::move(request_name), start, payload,
                 service_failure(read_word_be(payload, 0), FailureReason::wrong_state));
}

// A request that is allowed in `start`: answered `reply` (holes allowed), state unchanged.
Case allowed(std::string request_name, Start start, const Request& request, BytePattern reply,
             std::optional<Start> after = std::nullopt) {
  std::string name = "states/" + request_name + "_allowed_in_" + std::string(start_name(start));
  return Case{std::move(name),
              [start, after, payload = encode_request(request), reply = std::move(reply)](Session& session) {
                enter(session, start);
                session.expect("reply", payload, reply);
                expect_state(session, after.value_or(start));
              },
              true, true, {}};
}

Bytes set_config_refused() { return reply_bytes(SetConfigReply{kSetConfigRefused}); }

}  // namespace

void add_state_cases(std::vector<Case>& cases) {
  // D2: TRANS_MEASURE from IDLE and TRANS_IDLE from MEASURE must pass through ROTATE (spec 5).
  cases.push_back(wrong_state("TRANS_MEASURE", Start::idle, TransMeasure{}));
  cases.push_back(wrong_state("TRANS_IDLE", Start::measure, TransIdle{}));
  // D2: GET_PROFILE and CANCEL_PROFILE only in MEASURE.
  for (Start start : {Start::idle, Start::rotate}) {
    cases.push_back(wrong_state("GET_PROFILE", start, GetProfile{0, kFormatRange}));
    cases.push_back(wrong_state("CANCEL_PROFILE", start, CancelProfile{}));
  }
  // D2: SET_TIME_*, SET_FILTER outside MEASURE only; SET_FUNCTION in MEASURE answers FF FF.
  cases.push_back(wrong_state("SET_TIME_ABS", Start::measure, SetTimeAbs{1000}));
  cases.push_back(wrong_state("SET_TIME_REL", Start::measure, SetTimeRel{-10}));
  cases.push_back(wrong_state("SET_FILTER", Start::measure, SetFilter{kFilterItemNearField, 1}));
  cases.push_back(refused("SET_FUNCTION", Start::measure, encode_request(SetFunction{1, sector_function::kNoMeasurement, 3600, 0}),
                          reply_bytes(SetFunctionReply{kSetFunctionInvalid})));
  // D2: SET_CONFIG only in IDLE, elsewhere result 0x0001.
  for (Start start : {Start::rotate, Start::measure}) {
    cases.push_back(refused("SET_CONFIG", start, encode_request(SetConfig{GlobalConfig{1, 10, 4, false}}), set_config_refused()));
  }
  // D2: a transition to the current state answers the current status.
  cases.push_back(refused("TRANS_IDLE_to_current", Start::idle, encode_request(TransIdle{}),
                          reply_bytes(TransIdleReply{status(SensorMode::idle)})));
  cases.push_back(refused("TRANS_ROTATE_to_current", Start::rotate, encode_request(TransRotate{0}),
                          reply_bytes(TransRotateReply{status(SensorMode::rotate)})));
  cases.push_back(refused("TRANS_MEASURE_to_current", Start::measure, encode_request(TransMeasure{}),
                          reply_bytes(TransMeasureReply{status(SensorMode::measure), measure_return::kOk})));
  // D2: CANCEL_PROFILE in MEASURE with no stream answers the status block.
  cases.push_back(refused("CANCEL_PROFILE_without_stream", Start::measure, encode_request(CancelProfile{}),
                          reply_bytes(CancelProfileReply{status(SensorMode::measure)})));
  // Allowed: every GET_* everywhere (D2), SET_TIME_*/SET_FUNCTION/SET_FILTER in ROTATE (spec 5).
  for (Start start : {Start::rotate, Start::measure}) {
    cases.push_back(allowed("GET_CONFIG_global", start, GetConfig{key_word(ConfigKey::global)},
                            BytePattern::exactly(reply_bytes(GetConfigReply{GlobalConfig{1, 10, 4, false}}))));
    cases.push_back(allowed("GET_FUNCTION_s0", start, GetFunction{0},
                            BytePattern::exactly(reply_bytes(GetFunctionReply{0, sector_function::kNormalMeasurement, 2160}))));
    cases.push_back(allowed("GET_SIGNAL", start, GetSignal{},
                            BytePattern::exactly(reply_bytes(GetSignalReply{0})).with_hole(2, 2)));
    cases.push_back(allowed("GET_IDENTIFICATION_1", start, GetIdentification{ident_item::kSensorName},
                            BytePattern::exactly(Bytes{0x81, 0x01, 'L', 'D', '-', 'O', 'E', 'M', '1', '0', '0', '0'})));
    cases.push_back(allowed("GET_SYNC_CLOCK", start, GetSyncClock{},
                            BytePattern::exactly(reply_bytes(SyncClockReply{0})).with_hole(2, 2)));
    cases.push_back(allowed("SET_SIGNAL", start, SetSignal{0}, BytePattern::exactly(reply_bytes(SetSignalReply{0}))));
  }
  cases.push_back(allowed("SET_TIME_ABS", Start::rotate, SetTimeAbs{1000},
                          BytePattern::exactly(reply_bytes(SetTimeAbsReply{1000}))));
  cases.push_back(allowed("SET_FILTER", Start::rotate, SetFilter{kFilterItemNearField, 0},
                          BytePattern::exactly(reply_bytes(SetFilterReply{kFilterItemNearField}))));
  cases.push_back(allowed("SET_FUNCTION", Start::rotate, SetFunction{1, sector_function::kNoMeasurement, 3600, 0},
                          BytePattern::exactly(reply_bytes(SetFunctionReply{1}))));
  cases.push_back(allowed("DO_RESET_2_is_IDLE", Start::measure, DoReset{reset_level::kHaltToIdle},
                          BytePattern::exactly(reply_bytes(DoResetReply{reset_level::kHaltToIdle})), Start::idle));
}

}  // namespace ldoem::conformance
