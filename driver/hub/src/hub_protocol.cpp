// The hub's line protocol (docs/hub.md, grammar in hub_protocol.hpp).
#include "ldoem/hub/hub_protocol.hpp"

#include "hub_text.hpp"

namespace ldoem::hub {
namespace {

using base::Unexpected;

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

std::vector<std::string_view> split_spaces(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t position = 0;
  while (position < line.size()) {
    while (position < line.size() && (line[position] == ' ' || line[position] == '\t')) {
      ++position;
    }
    const std::size_t start = position;
    while (position < line.size() && line[position] != ' ' && line[position] != '\t') {
      ++position;
    }
    if (position > start) {
      tokens.push_back(line.substr(start, position - start));
    }
  }
  return tokens;
}

bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '.' || c == '-';
}

bool is_name(std::string_view token) {
  if (token.empty() || token.size() > kMaxTokenLength) {
    return false;
  }
  for (char c : token) {
    if (!is_name_char(c)) {
      return false;
    }
  }
  return true;
}

using text::format_double;
using text::hex_digit;
using text::parse_double;
using text::parse_integer;

std::string_view trim_line_end(std::string_view line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) {
    line.remove_suffix(1);
  }
  return line;
}

using Args = std::vector<std::string_view>;
using CommandResult = base::Expected<HubCommand, std::string>;

CommandResult fail_with(std::string detail) { return Unexpected<std::string>(std::move(detail)); }

std::optional<std::vector<driver::SectorDefinition>> parse_sectors(std::string_view text) {
  std::vector<driver::SectorDefinition> sectors;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    const std::size_t colon = item.find(':');
    if (colon == std::string_view::npos) {
      return std::nullopt;
    }
    const auto function = parse_integer<std::uint16_t>(item.substr(0, colon));
    const auto stop = parse_integer<std::uint16_t>(item.substr(colon + 1));
    if (!function || !stop) {
      return std::nullopt;
    }
    sectors.push_back({*function, *stop});
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
  }
  if (sectors.empty() || sectors.size() > protocol::kSectorCount) {
    return std::nullopt;
  }
  return sectors;
}

CommandResult parse_initialize(const Args& args) {
  InitializeRequest request;
  for (std::string_view arg : args) {
    const std::size_t equals = arg.find('=');
    const std::string_view key = arg.substr(0, equals);
    const std::string_view value = equals == std::string_view::npos ? std::string_view{} : arg.substr(equals + 1);
    if (key == "speed" && parse_integer<std::uint16_t>(value)) {
      request.motor_speed_hz = parse_integer<std::uint16_t>(value);
    } else if (key == "step" && parse_integer<std::uint16_t>(value)) {
      request.angle_step_ticks = parse_integer<std::uint16_t>(value);
    } else if (key == "sectors" && parse_sectors(value)) {
      request.sectors = *parse_sectors(value);
    } else {
      return fail_with("INITIALIZE: bad argument `" + std::string(arg) + "`");
    }
  }
  return HubCommand{request};
}

std::optional<std::optional<std::chrono::milliseconds>> parse_max_age(const Args& args) {
  if (args.empty()) {
    return std::optional<std::chrono::milliseconds>{};
  }
  const auto age = parse_integer<std::uint32_t>(args[0]);
  if (args.size() > 1 || !age) {
    return std::nullopt;
  }
  return std::optional<std::chrono::milliseconds>{std::chrono::milliseconds(*age)};
}

CommandResult parse_move(const Args& args) {
  if (args.size() < 3 || args.size() > 4) {
    return fail_with("MOVEMOTOR needs STEPS up|down full|half [RATE_HZ]");
  }
  MotorMove move;
  const auto steps = parse_integer<std::uint32_t>(args[0]);
  if (!steps) {
    return fail_with("MOVEMOTOR: bad step count `" + std::string(args[0]) + "`");
  }
  if (*steps > kMaxMoveSteps) {
    return fail_with("MOVEMOTOR: at most " + std::to_string(kMaxMoveSteps) + " steps per request");
  }
  move.steps = *steps;
  if (args[1] == "up") {
    move.direction = TiltDirection::increasing;
  } else if (args[1] == "down") {
    move.direction = TiltDirection::decreasing;
  } else {
    return fail_with("MOVEMOTOR: direction must be up or down");
  }
  if (args[2] == "full") {
    move.mode = StepMode::full_step;
  } else if (args[2] == "half") {
    move.mode = StepMode::half_step;
  } else {
    return fail_with("MOVEMOTOR: mode must be full or half");
  }
  if (args.size() == 4) {
    const auto rate = parse_double(args[3]);
    if (!rate || !(*rate >= kMinStepRateHz && *rate <= kMaxStepRateHz)) {
      return fail_with("MOVEMOTOR: step rate `" + std::string(args[3]) + "` is not a number of Hz in [" +
                       format_double(kMinStepRateHz) + ", " + format_double(kMaxStepRateHz) + "]");
    }
    move.step_rate_hz = *rate;
  }
  return HubCommand{move};
}

CommandResult parse_no_args(const Args& args, HubCommand command) {
  if (!args.empty()) {
    return fail_with(std::string(command_name(command)) + " takes no argument");
  }
  return command;
}

// nullopt: unknown command name.
std::optional<CommandResult> parse_command(std::string_view name, const Args& args) {
  if (name == "INITIALIZE") {
    return parse_initialize(args);
  }
  if (name == "ROTATE") {
    if (args.empty()) {
      return CommandResult{HubCommand{RotateCommand{}}};
    }
    const auto hz = parse_integer<std::uint16_t>(args[0]);
    if (args.size() > 1 || !hz) {
      return fail_with("ROTATE takes one frequency in Hz");
    }
    return CommandResult{HubCommand{RotateCommand{*hz}}};
  }
  if (name == "MEASURE") {
    return parse_no_args(args, MeasureCommand{});
  }
  if (name == "IDLE") {
    return parse_no_args(args, IdleCommand{});
  }
  if (name == "DEVICES") {
    return parse_no_args(args, DevicesCommand{});
  }
  if (name == "GET2DPROFILE" || name == "STATUS") {
    const auto max_age = parse_max_age(args);
    if (!max_age) {
      return fail_with(std::string(name) + " takes one maximum age in ms");
    }
    if (name == "STATUS") {
      return CommandResult{HubCommand{StatusCommand{*max_age}}};
    }
    return CommandResult{HubCommand{ProfileCommand{*max_age}}};
  }
  if (name == "MOVEMOTOR") {
    return parse_move(args);
  }
  return std::nullopt;
}

}  // namespace

std::string_view command_name(const HubCommand& command) {
  return std::visit(Overloaded{
                        [](const InitializeRequest&) { return std::string_view("INITIALIZE"); },
                        [](const RotateCommand&) { return std::string_view("ROTATE"); },
                        [](const MeasureCommand&) { return std::string_view("MEASURE"); },
                        [](const IdleCommand&) { return std::string_view("IDLE"); },
                        [](const ProfileCommand&) { return std::string_view("GET2DPROFILE"); },
                        [](const MotorMove&) { return std::string_view("MOVEMOTOR"); },
                        [](const StatusCommand&) { return std::string_view("STATUS"); },
                        [](const DevicesCommand&) { return std::string_view("DEVICES"); },
                    },
                    command);
}

bool changes_device(const HubCommand& command) {
  return std::holds_alternative<InitializeRequest>(command) || std::holds_alternative<RotateCommand>(command) ||
         std::holds_alternative<MeasureCommand>(command) || std::holds_alternative<IdleCommand>(command) ||
         std::holds_alternative<MotorMove>(command);
}

base::Expected<HubRequest, RequestParseError> parse_request(std::string_view line) {
  const Args tokens = split_spaces(trim_line_end(line));
  const auto failure = [](std::string id, std::string kind, std::string detail) {
    return Unexpected<RequestParseError>({std::move(id), std::move(kind), std::move(detail)});
  };
  if (tokens.empty() || !is_name(tokens[0])) {
    return failure(std::string(kUnknownId), "bad_request", "a request starts with an ID of [A-Za-z0-9_.-]");
  }
  std::string id(tokens[0]);
  if (tokens.size() < 3) {
    return failure(id, "bad_request", "a request is: ID DEVICE COMMAND [ARG ...]");
  }
  if (tokens[1] != kAllDevices && !is_name(tokens[1])) {
    return failure(id, "bad_request", "bad device name `" + std::string(tokens[1]) + "`");
  }
  const Args args(tokens.begin() + 3, tokens.end());
  const auto command = parse_command(tokens[2], args);
  if (!command) {
    return failure(id, "unknown_command", "unknown command `" + std::string(tokens[2]) + "`");
  }
  if (!command->has_value()) {
    return failure(id, "bad_request", command->error());
  }
  const bool wants_all = std::holds_alternative<DevicesCommand>(command->value());
  if (wants_all != (tokens[1] == kAllDevices)) {
    return failure(id, "bad_request", "DEVICES takes the device `*`, every other command a device name");
  }
  return HubRequest{id, std::string(tokens[1]), command->value()};
}

std::string format_request(const HubRequest& request) {
  std::string line = request.id + " " + request.device + " " + std::string(command_name(request.command));
  const auto age_argument = [&line](const std::optional<std::chrono::milliseconds>& age) {
    if (age) {
      line += " " + std::to_string(age->count());
    }
  };
  std::visit(Overloaded{
                 [&](const InitializeRequest& init) {
                   if (init.motor_speed_hz) {
                     line += " speed=" + std::to_string(*init.motor_speed_hz);
                   }
                   if (init.angle_step_ticks) {
                     line += " step=" + std::to_string(*init.angle_step_ticks);
                   }
                   for (std::size_t i = 0; i < init.sectors.size(); ++i) {
                     line += i == 0 ? " sectors=" : ",";
                     line += std::to_string(init.sectors[i].function) + ":" +
                             std::to_string(init.sectors[i].stop_ticks);
                   }
                 },
                 [&](const RotateCommand& rotate) {
                   if (rotate.frequency_hz != 0) {
                     line += " " + std::to_string(rotate.frequency_hz);
                   }
                 },
                 [&](const ProfileCommand& profile) { age_argument(profile.max_age); },
                 [&](const StatusCommand& status) { age_argument(status.max_age); },
                 [&](const MotorMove& move) {
                   line += " " + std::to_string(move.steps);
                   line += move.direction == TiltDirection::increasing ? " up" : " down";
                   line += move.mode == StepMode::half_step ? " half" : " full";
                   if (move.step_rate_hz) {
                     line += " " + format_double(*move.step_rate_hz);
                   }
                 },
                 [](const auto&) {},
             },
             request.command);
  return line;
}

std::optional<std::string> HubReply::field(std::string_view key) const {
  for (const auto& [name, value] : fields) {
    if (name == key) {
      return value;
    }
  }
  return std::nullopt;
}

base::Expected<HubReply, ReplyParseError> parse_reply(std::string_view line) {
  line = trim_line_end(line);
  const auto failure = [](std::string detail) { return Unexpected<ReplyParseError>({std::move(detail)}); };
  if (line.find_first_of("\r\n") != std::string_view::npos) {
    return failure("a reply is one line (a line break inside it)");  // found by fuzz_hub_request
  }
  const Args tokens = split_spaces(line);
  if (tokens.size() < 3) {
    return failure("a reply is: ID OK COMMAND ... or ID ERR KIND MESSAGE");
  }
  HubReply reply;
  reply.id = std::string(tokens[0]);
  if (tokens[1] == "ERR") {
    reply.ok = false;
    reply.error_kind = std::string(tokens[2]);
    // The message is the rest of the line after KIND, spaces kept.
    const std::size_t kind_end = static_cast<std::size_t>(tokens[2].data() - line.data()) + tokens[2].size();
    std::string_view message = line.substr(kind_end);
    while (!message.empty() && message.front() == ' ') {
      message.remove_prefix(1);
    }
    reply.error_message = std::string(message);
    return reply;
  }
  if (tokens[1] != "OK") {
    return failure("the second token of a reply is OK or ERR");
  }
  reply.command = std::string(tokens[2]);
  for (std::size_t i = 3; i < tokens.size(); ++i) {
    const std::size_t equals = tokens[i].find('=');
    if (equals == std::string_view::npos || equals == 0) {
      return failure("reply field `" + std::string(tokens[i]) + "` is not KEY=VALUE");
    }
    auto value = unescape_value(tokens[i].substr(equals + 1));
    if (!value) {
      return failure("reply field `" + std::string(tokens[i]) + "` has a bad escape");
    }
    reply.fields.emplace_back(std::string(tokens[i].substr(0, equals)), std::move(*value));
  }
  return reply;
}

std::string format_reply(const HubReply& reply) {
  std::string line = reply.id;
  if (!reply.ok) {
    line += " ERR " + reply.error_kind + " ";
    for (char c : reply.error_message) {
      line.push_back(c == '\n' || c == '\r' ? ' ' : c);
    }
    return line;
  }
  line += " OK " + reply.command;
  for (const auto& [key, value] : reply.fields) {
    line += " " + key + "=" + escape_value(value);
  }
  return line;
}

HubReply ok_reply(std::string id, std::string command, std::vector<ReplyField> fields) {
  HubReply reply;
  reply.id = std::move(id);
  reply.command = std::move(command);
  reply.fields = std::move(fields);
  return reply;
}

HubReply error_reply(std::string id, std::string kind, std::string message) {
  HubReply reply;
  reply.id = std::move(id);
  reply.ok = false;
  reply.error_kind = std::move(kind);
  reply.error_message = std::move(message);
  return reply;
}

std::string escape_value(std::string_view value) {
  std::string text;
  text.reserve(value.size());
  for (char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte <= 0x20 || byte >= 0x7F || c == '%') {
      text.push_back('%');
      text.push_back(hex_digit(byte >> 4));
      text.push_back(hex_digit(byte));
    } else {
      text.push_back(c);
    }
  }
  return text;
}

std::optional<std::string> unescape_value(std::string_view text) {
  std::string value;
  value.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      value.push_back(text[i]);
      continue;
    }
    if (i + 2 >= text.size()) {
      return std::nullopt;
    }
    const auto byte = parse_integer<std::uint8_t>(text.substr(i + 1, 2), 16);
    if (!byte) {
      return std::nullopt;
    }
    value.push_back(static_cast<char>(*byte));
    i += 2;
  }
  return value;
}

}  // namespace ldoem::hub
