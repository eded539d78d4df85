// The hub's message protocol (docs/hub.md): one request or reply per line, ASCII, LF-terminated
// (a CR before the LF is ignored). parse_* and format_* are pure and inverse; the grammar below
// doubles as the test table in tests/hub/hub_protocol_test.cpp.
//
// Request:  ID DEVICE COMMAND [ARG ...]
//   ID      1..32 of [A-Za-z0-9_.-], chosen by the client; the reply carries it back
//   DEVICE  1..32 of [A-Za-z0-9_.-], a device name from the hub's configuration, or `*` (DEVICES)
//   7 INITIALIZE [speed=HZ] [step=TICKS] [sectors=FUNC:STOP,...]
//   7 ROTATE [HZ]                       (0 or absent: the configured speed)
//   7 MEASURE | 7 IDLE
//   7 GET2DPROFILE [MAX_AGE_MS]         (absent: the hub's --max-age-ms; 0: always a new one)
//   7 MOVEMOTOR STEPS up|down full|half [RATE_HZ]
//   7 STATUS [MAX_AGE_MS]
//   7 * DEVICES
// Reply:    ID OK COMMAND [KEY=VALUE ...]      values percent-escaped (%20 for a space)
//           ID ERR KIND MESSAGE...             KIND one token (error_kind_token), MESSAGE free text
// Unsolicited lines use the ID `*` (the greeting `* OK HELLO femh=F3 protocol=1`, and a device's
// health: `* OK FAULT device=NAME handler=Bn kind=KIND recovery=R [status_byte=N] detail=TEXT`,
// `* OK RECOVERED device=NAME handler=Bn`). A line that cannot be parsed far enough to know its
// ID is answered with the ID `-`.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "ldoem/hub/device_vocabulary.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::hub {

inline constexpr int kHubProtocolVersion = 1;
inline constexpr std::size_t kMaxTokenLength = 32;
// Longer request lines are refused (bad_request); replies are not limited (profiles are long).
inline constexpr std::size_t kMaxRequestLineLength = 1024;
inline constexpr std::string_view kAllDevices = "*";
inline constexpr std::string_view kUnsolicitedId = "*";
inline constexpr std::string_view kUnknownId = "-";

struct RotateCommand { std::uint16_t frequency_hz = 0; bool operator==(const RotateCommand&) const = default; };
struct MeasureCommand { bool operator==(const MeasureCommand&) const = default; };
struct IdleCommand { bool operator==(const IdleCommand&) const = default; };
struct ProfileCommand {
  std::optional<std::chrono::milliseconds> max_age;
  bool operator==(const ProfileCommand&) const = default;
};
struct StatusCommand {
  std::optional<std::chrono::milliseconds> max_age;
  bool operator==(const StatusCommand&) const = default;
};
struct DevicesCommand { bool operator==(const DevicesCommand&) const = default; };

using HubCommand = std::variant<InitializeRequest, RotateCommand, MeasureCommand, IdleCommand,
                                ProfileCommand, MotorMove, StatusCommand, DevicesCommand>;

// "INITIALIZE", "ROTATE", ..., "GET2DPROFILE", "MOVEMOTOR", "STATUS", "DEVICES".
std::string_view command_name(const HubCommand& command);
// Commands that change the device (their reply makes the cached profile stale).
bool changes_device(const HubCommand& command);

struct HubRequest {
  std::string id;
  std::string device;
  HubCommand command;
  bool operator==(const HubRequest&) const = default;
};

struct RequestParseError {
  std::string id;      // the ID when it could be read, else kUnknownId
  std::string kind;    // "bad_request" or "unknown_command"
  std::string detail;  // one line
  bool operator==(const RequestParseError&) const = default;
};

base::Expected<HubRequest, RequestParseError> parse_request(std::string_view line);
// Without the line feed.
std::string format_request(const HubRequest& request);

using ReplyField = std::pair<std::string, std::string>;

struct HubReply {
  std::string id;
  bool ok = true;
  std::string command;               // OK: the command's name
  std::vector<ReplyField> fields;    // OK: unescaped values, in order
  std::string error_kind;            // ERR
  std::string error_message;         // ERR
  bool operator==(const HubReply&) const = default;

  // The first value of `key`, if present.
  std::optional<std::string> field(std::string_view key) const;
};

struct ReplyParseError {
  std::string detail;
  bool operator==(const ReplyParseError&) const = default;
};

base::Expected<HubReply, ReplyParseError> parse_reply(std::string_view line);
// Without the line feed; values are escaped, an error message has its line breaks replaced.
std::string format_reply(const HubReply& reply);

HubReply ok_reply(std::string id, std::string command, std::vector<ReplyField> fields = {});
HubReply error_reply(std::string id, std::string kind, std::string message);

// Percent-escaping of values: bytes <= 0x20, >= 0x7F and '%' become %XX.
std::string escape_value(std::string_view value);
std::optional<std::string> unescape_value(std::string_view text);

// --------------------------------------------------- error kinds on the wire and back
// ErrorKind as one token: timeout busy interrupted framing connection_closed service_failure
// unexpected_reply refused system unsupported invalid_argument wrong_state.
std::string_view error_kind_token(ErrorKind kind);
// The hub's own kinds (bad_request, unknown_command, unknown_device) map to invalid_argument.
ErrorKind error_kind_from_token(std::string_view token);
// driver::Recovery as one token: retry reconnect reset_device none.
std::string_view recovery_token(driver::Recovery recovery);

// ------------------------------------------------------------- typed reply fields
// status=HEX8 (the 4-byte status block) mode=idle|rotate|measure|error|0xN motor=ok|...
std::vector<ReplyField> status_fields(const StatusBlock& status);
std::optional<StatusBlock> status_from(const HubReply& reply);
// tilt_half_steps=N tilt_deg=X
std::vector<ReplyField> tilt_fields(const TiltPosition& tilt);
std::optional<TiltPosition> tilt_from(const HubReply& reply);
// tilt_half_steps=N tilt_deg=X profile=HEX (the 0x8301 payload, spec 3.5)
std::vector<ReplyField> profile_fields(const ProfileSample& sample);
std::optional<ProfileSample> profile_from(const HubReply& reply);
// status fields, then ident.XXXX=TEXT per identification item (XXXX: item, 4 hex digits)
std::vector<ReplyField> info_fields(const DeviceInfo& info);
std::optional<DeviceInfo> info_from(const HubReply& reply);

}  // namespace ldoem::hub
