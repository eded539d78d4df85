#include "ldoem/ctl/ctl_options.hpp"

#include <CLI/CLI.hpp>

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/numbers.hpp"
#include "ldoem/control_socket/command_table.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <utility>

namespace ldoem::ctl {
namespace {

using nlohmann::json;

// "GET_STATUS:3" -> {"service": "GET_STATUS", <count_key>: 3}
std::optional<json> service_count(const std::string& text, const char* count_key) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) return std::nullopt;
  try {
    std::size_t used = 0;
    const unsigned long long count = std::stoull(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) return std::nullopt;
    return json{{"service", text.substr(0, colon)}, {count_key, count}};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// "2,0.5,0" -> three numbers. Read here rather than by CLI11, whose help would show the value as
// "X,Y,Z x 3".
std::optional<std::vector<double>> three_numbers(const std::string& text) {
  std::vector<double> numbers;
  std::size_t start = 0;
  for (std::size_t comma = 0; comma != std::string::npos; start = comma + 1) {
    comma = text.find(',', start);
    const auto number = base::parse_double(std::string_view(text).substr(start, comma == std::string::npos ? comma : comma - start));
    if (!number) return std::nullopt;
    numbers.push_back(*number);
  }
  if (numbers.size() != 3) return std::nullopt;
  return numbers;
}

// The first word that is neither an option nor the value of one of the top-level options: the
// command the user meant, so that a misspelt one is named ("unknown command `bogus`").
std::optional<std::string> command_word(const std::vector<std::string>& args) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (!word.starts_with("-")) return word;
    if (word.find('=') == std::string::npos && (word == "--control" || word == "--timeout" || word == "--scanner")) ++i;
  }
  return std::nullopt;
}

// "inject-fault, clear-fault, ... and power-cycle": the table's per-scanner commands.
std::string per_scanner_commands() {
  std::vector<std::string> names;
  for (const auto& command : control_socket::command_table()) {
    if (command.per_scanner) names.push_back(command.name);
  }
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  }
  return text;
}

// What --help shows as the value of a table argument ldoem-ctl has no option of its own for.
std::string value_name(control_socket::ArgumentType type) {
  switch (type) {
    case control_socket::ArgumentType::text: return "TEXT";
    case control_socket::ArgumentType::number: return "NUMBER";
    case control_socket::ArgumentType::count: return "N";
    case control_socket::ArgumentType::boolean: return "true|false";
    case control_socket::ArgumentType::object:
    case control_socket::ArgumentType::list: return "JSON";
  }
  return "JSON";
}

}  // namespace

std::variant<CtlPlan, CtlExit> parse_ctl_options(const std::vector<std::string>& args) {
  CLI::App app{"ldoem-ctl: talk to ldoem-emud's control socket (ldoem-emud --control PATH).\n"
               "Exit codes: 0 done, 1 error reply or daemon unreachable, 2 usage.",
               "ldoem-ctl"};
  app.footer("Examples:\n"
             "  ldoem-ctl --control /tmp/ldoem.ctl inject-fault motor_stall --duration 2\n"
             "  ldoem-ctl --control /tmp/ldoem.ctl inject-fault drop_reply --on GET_STATUS:3 --transport tcp\n"
             "  ldoem-ctl --control /tmp/ldoem.ctl --scanner side query-status\n"
             "  ldoem-ctl --control /tmp/ldoem.ctl query-faults\n"
             "  ldoem-ctl --control /tmp/ldoem.ctl events --count 5 --timeout 10\n"
             "  ldoem-ctl --control /tmp/ldoem.ctl move-object door --position 2,0.5,0 --rpy 0,0,90 --at 3\n"
             "Fault kinds and their bytes: docs/faults.md");
  // The command and --control are checked after parsing, so that --help-all, --version and
  // --completion need neither, and a missing one is named in the tools' words.
  app.require_subcommand(0, 1);
  app.set_help_flag("-h,--help", "the most used options and the commands");
  app.set_help_all_flag("--help-all", "this text, every command's options too");
  app.set_version_flag("--version", std::string("ldoem-ctl ") + LDOEM_VERSION, "print the name and version");
  std::string completion_shell;
  app.add_option("--completion", completion_shell, "print a bash completion")->check(CLI::IsMember({"bash"}).description(""))
      ->type_name("bash");
  CtlPlan plan;
  double timeout_s = 5.0;
  app.add_option("--control", plan.control_path, "the daemon's control socket (required)")->type_name("PATH");
  app.add_flag("--json", plan.json_output, "print the raw JSON lines");
  base::take_text(app, "--timeout", [&timeout_s](const std::string& value) -> std::optional<std::string> {
       const auto seconds = base::parse_double(value);
       if (!seconds || *seconds < 0.0 || *seconds > 86400.0) return "`" + value + "` is not a number of seconds in 0..86400";
       timeout_s = *seconds;
       return std::nullopt;
     })
      ->description("seconds to wait for the reply, 0..86400 (events: to follow; 0 = forever) [5]")->type_name("SECONDS");
  std::string scanner;
  app.add_option("--scanner", scanner, "the scanner a fault command acts on, by its scene name (several scanners "
                                       "in one daemon; default: the first)")->type_name("NAME");

  // Every command of the control socket's table (command_table.hpp) is a command here, with the
  // table's help. The ones below get options of their own; any other sends each argument of its
  // schema given as --NAME VALUE (VALUE read as JSON, else as a text).
  std::map<std::string, CLI::App*, std::less<>> table_commands;
  for (const auto& command : control_socket::command_table()) {
    table_commands[command.name] = app.add_subcommand(command.name, command.help);
  }
  const auto command_of = [&table_commands](std::string_view name) { return table_commands.find(name)->second; };
  json arguments = json::object();
  auto* inject = command_of("inject-fault");
  std::string kind;
  inject->add_option("kind", kind, "a D11 fault name (motor_stall, drop_reply, ...)")->required()->type_name("KIND");
  struct NumberOption {
    const char* flag;
    const char* key;
    const char* type;  // what --help shows as the value
    const char* help;
    double value = 0.0;
  };
  std::vector<NumberOption> numbers{
      {"--duration", "duration_s", "SECONDS", "how long it stays active"},
      {"--count", "count", "N", "telegrams (or lost steps) it affects"},
      {"--at", "at_s", "SECONDS", "simulated time at which it starts"},
      {"--probability", "probability", "P", "0..1 per request, drawn from the scene seed"},
      {"--from-deg", "from_deg", "DEG", "blind: sector start"},
      {"--to-deg", "to_deg", "DEG", "blind: sector end"},
      {"--fraction", "fraction", "F", "0..1, blind / window_dirt fraction"},
      {"--delay", "delay_s", "SECONDS", "delay_reply: the delay"},
      {"--bytes-kept", "bytes_kept", "N", "truncate_reply: bytes kept"},
      {"--bytes", "bytes", "N", "garbage: bytes inserted"},
      {"--bytes-per-s", "bytes_per_s", "N", "bandwidth: bytes per second"},
      {"--off", "off_s", "SECONDS", "power_cycle: time off"},
  };
  std::vector<CLI::Option*> number_options;
  for (NumberOption& number : numbers) {
    number_options.push_back(inject->add_option(number.flag, number.value, number.help)->type_name(number.type));
  }
  std::string transport, service, on, every;
  inject->add_option("--transport", transport, "tcp, serial, can, lpt or any")->type_name("TRANSPORT");
  inject->add_option("--service", service, "only replies to this service (GET_STATUS, ...)")->type_name("SERVICE");
  inject->add_option("--on", on, "on the Nth request of SERVICE")->type_name("SERVICE:N");
  inject->add_option("--every", every, "on every Nth request of SERVICE")->type_name("SERVICE:N");

  auto* clear = command_of("clear-fault");
  std::optional<std::uint64_t> clear_id;
  clear->add_option("id", clear_id, "the id inject-fault or query-faults gave")->type_name("ID");
  auto* power = command_of("power-cycle");
  std::optional<double> off_s;
  power->add_option("--off", off_s, "seconds off (default 1)")->type_name("SECONDS");
  auto* events = app.add_subcommand("events", "print event lines as they come");
  std::optional<std::uint64_t> event_count;
  events->add_option("--count", event_count, "stop after this many events")->type_name("N");
  // D12 runtime changes (docs/dynamic-scenes.md "Runtime changes").
  auto* move = command_of("move-object");
  std::string move_name;
  std::string position_text, rpy_text;
  std::optional<double> move_at;
  bool keep_velocity = false;
  move->add_option("name", move_name, "the object's name: in the scene")->required()->type_name("NAME");
  move->add_option("--position", position_text, "in metres (required)")->type_name("X,Y,Z");
  move->add_option("--rpy", rpy_text, "in degrees (default 0,0,0)")->type_name("ROLL,PITCH,YAW");
  move->add_option("--at", move_at, "device time (default: now)")->type_name("SECONDS");
  move->add_flag("--keep-velocity", keep_velocity, "a dynamics body keeps its velocity (default: at rest)");
  auto* add = command_of("add-object");
  std::string object_text;
  std::optional<double> add_at;
  add->add_option("object", object_text, "JSON, e.g. '{\"name\": \"crate\", \"box\": {\"size_m\": [1, 1, 1]}}'")
      ->required()->type_name("JSON");
  add->add_option("--at", add_at, "device time (default: now)")->type_name("SECONDS");
  auto* remove = command_of("remove-object");
  std::string remove_name;
  std::optional<double> remove_at;
  remove->add_option("name", remove_name, "the object's name")->required()->type_name("NAME");
  remove->add_option("--at", remove_at, "device time (default: now)")->type_name("SECONDS");
  auto* send = app.add_subcommand("send", "send one raw JSON request line");
  std::string raw;
  send->add_option("request", raw, "a JSON object")->required()->type_name("JSON");
  // The table's other commands: their arguments as options, by the schema.
  const std::vector<CLI::App*> own{inject, clear, power, move, add, remove};
  std::deque<std::string> generic_values;  // a deque: the options keep pointers into it
  std::map<const CLI::App*, std::vector<std::pair<std::string, CLI::Option*>>> generic_options;
  for (const auto& command : control_socket::command_table()) {
    CLI::App* sub = command_of(command.name);
    if (std::find(own.begin(), own.end(), sub) != own.end()) continue;
    auto& options = generic_options[sub];
    for (const auto& argument : command.arguments) {
      generic_values.emplace_back();
      options.emplace_back(argument.name, sub->add_option("--" + argument.name, generic_values.back(), argument.what)
                                              ->type_name(value_name(argument.type)));
    }
  }

  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    // A command's own help ("inject-fault --help") is short: all of it.
    if (!app.get_subcommands().empty()) return CtlExit{kExitOk, app.help()};
    // The commands: the table's, then ldoem-ctl's own (events, send).
    std::vector<std::string_view> brief{"--control", "--scanner", "--timeout", "--json"};
    for (const auto& command : control_socket::command_table()) brief.push_back(command.name);
    for (const std::string_view extra : {"events", "send", "--help", "--version"}) brief.push_back(extra);
    return CtlExit{kExitOk, base::brief_help("ldoem-ctl", app.help(),
                                             "Talk to ldoem-emud's control socket: inject faults, query, move objects.", brief)};
  } catch (const CLI::CallForAllHelp&) {
    return CtlExit{kExitOk, app.help("", CLI::AppFormatMode::All)};
  } catch (const CLI::CallForVersion&) {
    return CtlExit{kExitOk, app.version()};
  } catch (const CLI::ParseError& error) {
    std::string known;
    bool is_command = false;
    const auto word = command_word(args);
    for (const CLI::App* command : std::as_const(app).get_subcommands([](const CLI::App*) { return true; })) {
      known += (known.empty() ? "" : ", ") + command->get_name();
      is_command = is_command || (word && command->get_name() == *word);
    }
    if (word && !is_command) {
      return CtlExit{kExitUsage, "ldoem-ctl: unknown command '" + *word + "' (commands: " + known + ")"};
    }
    const std::vector<std::string> extras = app.remaining();
    if (!extras.empty() && extras.front().starts_with("-")) {
      return CtlExit{kExitUsage, base::usage_error_line("ldoem-ctl", "unknown option `" + extras.front() + "`")};
    }
    return CtlExit{kExitUsage, base::usage_error_line("ldoem-ctl", error.what())};
  }
  if (!completion_shell.empty()) return CtlExit{kExitOk, base::completion_script(app, "ldoem-ctl")};
  if (app.get_subcommands().empty()) {
    std::string known;
    for (const CLI::App* command : std::as_const(app).get_subcommands([](const CLI::App*) { return true; })) {
      known += (known.empty() ? "" : ", ") + command->get_name();
    }
    return CtlExit{kExitUsage, "ldoem-ctl: no command given (commands: " + known + ")"};
  }
  if (plan.control_path.empty()) return CtlExit{kExitUsage, base::usage_error_line("ldoem-ctl", "--control PATH is required")};
  plan.timeout = std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000.0));
  auto request = [](const std::string& command, json args) {
    json line{{"execute", command}};
    if (!args.empty()) line["arguments"] = std::move(args);
    return line;
  };
  auto usage = [](const std::string& text) { return CtlExit{kExitUsage, base::usage_error_line("ldoem-ctl", text)}; };

  if (inject->parsed()) {
    arguments["kind"] = kind;
    for (std::size_t i = 0; i < numbers.size(); ++i) {
      if (number_options[i]->count() > 0) arguments[numbers[i].key] = numbers[i].value;
    }
    if (!transport.empty()) arguments["transport"] = transport;
    if (!service.empty()) arguments["service"] = service;
    if (!on.empty()) {
      auto trigger = service_count(on, "nth");
      if (!trigger) return usage("--on wants SERVICE:N, e.g. GET_STATUS:3");
      arguments["on"] = *trigger;
    }
    if (!every.empty()) {
      auto trigger = service_count(every, "count");
      if (!trigger) return usage("--every wants SERVICE:N, e.g. GET_PROFILE:10");
      arguments["every"] = *trigger;
    }
    plan.request = request("inject-fault", arguments);
  } else if (clear->parsed()) {
    plan.request = request("clear-fault", clear_id ? json{{"id", *clear_id}} : json::object());
  } else if (power->parsed()) {
    plan.request = request("power-cycle", off_s ? json{{"off_s", *off_s}} : json::object());
  } else if (move->parsed()) {
    const auto position = three_numbers(position_text);
    if (!position) return usage("--position wants X,Y,Z in metres, e.g. 2,0.5,0");
    json args{{"name", move_name}, {"position_m", *position}};
    if (!rpy_text.empty()) {
      const auto rpy = three_numbers(rpy_text);
      if (!rpy) return usage("--rpy wants ROLL,PITCH,YAW in degrees, e.g. 0,0,90");
      args["rpy_deg"] = *rpy;
    }
    if (move_at) args["at_s"] = *move_at;
    if (keep_velocity) args["keep_velocity"] = true;
    plan.request = request("move-object", args);
  } else if (add->parsed()) {
    json object = json::parse(object_text, nullptr, false);
    if (object.is_discarded() || !object.is_object()) return usage("add-object wants one JSON object");
    json args{{"object", object}};
    if (add_at) args["at_s"] = *add_at;
    plan.request = request("add-object", args);
  } else if (remove->parsed()) {
    json args{{"name", remove_name}};
    if (remove_at) args["at_s"] = *remove_at;
    plan.request = request("remove-object", args);
  } else if (events->parsed()) {
    plan.follow_events = true;
    plan.event_count = event_count;
  } else if (send->parsed()) {
    json line = json::parse(raw, nullptr, false);
    if (line.is_discarded() || !line.is_object()) return usage("send wants one JSON object");
    plan.request = line;
  } else {
    for (const auto& [sub, options] : generic_options) {
      if (!sub->parsed()) continue;
      json args = json::object();
      for (const auto& [name, option] : options) {
        if (option->count() == 0) continue;
        const std::string text = option->as<std::string>();
        json value = json::parse(text, nullptr, false);
        args[name] = value.is_discarded() ? json(text) : value;
      }
      plan.request = request(sub->get_name(), args);
    }
  }
  if (!scanner.empty()) {
    // Only the table's per-scanner commands act on one scanner (docs/faults.md); the others on
    // the daemon.
    const std::string command = plan.request ? plan.request->value("execute", "") : "";
    const control_socket::CommandSpec* spec = control_socket::find_command(command);
    if (send->parsed() || spec == nullptr || !spec->per_scanner) {
      return usage("--scanner: only with " + per_scanner_commands());
    }
    (*plan.request)["arguments"]["scanner"] = scanner;
  }
  return plan;
}

}  // namespace ldoem::ctl
