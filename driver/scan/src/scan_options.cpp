#include "ldoem/scan/scan_options.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "ldoem/base/command_line.hpp"
#include "ldoem/base/device_constants.hpp"
#include "ldoem/base/endpoint.hpp"
#include "ldoem/base/numbers.hpp"
#include "ldoem/driver/device.hpp"

namespace ldoem::scan {
namespace {

using base::Unexpected;
constexpr double kMaxTimeoutSeconds = 7.0 * 24 * 3600;  // a week
// Enough for any flaky link; a bound so a typo cannot make a dead device hold a scan for hours.
constexpr std::uint32_t kMaxRetries = 100;
// Reconnect bounds: at most an hour of a 60 s pause after 60 attempts, never an endless wait.
constexpr std::uint32_t kMaxReconnectAttempts = 1000;
constexpr double kMaxReconnectIntervalSeconds = 60.0;
constexpr double kMaxReconnectBackoff = 10.0;
using OptionsResult = base::Expected<ScanOptions, std::string>;

Unexpected<std::string> usage_error(std::string text) { return Unexpected<std::string>(std::move(text)); }

using base::parse_double;

std::optional<Vector3> parse_vector(std::string_view text) {
  double values[3];
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = text.find(',');
    if ((i < 2) != (comma != std::string_view::npos)) {
      return std::nullopt;
    }
    const auto value = parse_double(text.substr(0, comma));
    if (!value) {
      return std::nullopt;
    }
    values[i] = *value;
    text = i < 2 ? text.substr(comma + 1) : std::string_view{};
  }
  return Vector3{values[0], values[1], values[2]};
}

using Setter = std::function<std::optional<std::string>(ScanOptions&, std::string_view)>;

Setter number_into(double ScanOptions::*field, bool positive) {
  return [field, positive](ScanOptions& options, std::string_view value) -> std::optional<std::string> {
    const auto number = parse_double(value);
    if (!number || (positive && *number <= 0.0) || *number < 0.0) {
      return "`" + std::string(value) + "` is not a " + (positive ? "positive" : "non-negative") + " number";
    }
    options.*field = *number;
    return std::nullopt;
  };
}

// The endpoint grammar of every tool (docs/endpoints.md); ldoem-scan connects. The problem
// names the option itself (an old spelling: "--lpt pty:/x is the old spelling; write ...").
std::optional<std::string> set_endpoint(std::optional<driver::Endpoint>& slot, std::string_view option,
                                        std::string_view value, base::EndpointExpect expect) {
  auto endpoint = base::parse_endpoint(value, base::EndpointUse{base::EndpointSide::connect, expect});
  if (!endpoint) {
    return base::describe_for_option(option, endpoint.error());
  }
  slot = endpoint.value();
  return std::nullopt;
}

const std::map<std::string_view, Setter>& setters() {
  static const std::map<std::string_view, Setter> table{
      {"--device",
       [](ScanOptions& o, std::string_view v) { return set_endpoint(o.device, "--device", v, base::EndpointExpect::scanner); }},
      {"--lpt", [](ScanOptions& o, std::string_view v) { return set_endpoint(o.lpt, "--lpt", v, base::EndpointExpect::lpt); }},
      {"--hub",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         auto address = hub::parse_listen_address(v);
         if (!address) {
           return address.error();
         }
         o.hub = address.value();
         return std::nullopt;
       }},
      {"--hub-device",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         o.hub_device = std::string(v);
         return std::nullopt;
       }},
      {"--horizontal-apex", number_into(&ScanOptions::horizontal_apex_deg, true)},
      {"--horizontal-resolution", number_into(&ScanOptions::horizontal_resolution_deg, true)},
      {"--vertical-apex", number_into(&ScanOptions::vertical_apex_deg, false)},
      {"--vertical-resolution", number_into(&ScanOptions::vertical_resolution_deg, true)},
      {"--step-rate",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         // MOVEMOTOR's range (driver/device.hpp): a tiny rate would make every move refused.
         const auto rate = parse_double(v);
         if (!rate || !(*rate >= driver::kMinStepRateHz && *rate <= driver::kMaxStepRateHz)) {
           return "`" + std::string(v) + "` is not a step rate of " + std::to_string(static_cast<int>(driver::kMinStepRateHz)) +
                  ".." + std::to_string(static_cast<int>(driver::kMaxStepRateHz)) + " Hz";
         }
         o.step_rate_hz = *rate;
         return std::nullopt;
       }},
      {"--speed",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto value = base::parse_integer<std::uint16_t>(v);
         if (!value || *value < base::kMinMotorSpeedHz || *value > base::kMaxMotorSpeedHz) {
           return "`" + std::string(v) + "` is not a motor speed of 5..20 Hz (spec 6)";
         }
         o.speed_hz = *value;
         return std::nullopt;
       }},
      {"--out",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         o.out_path = std::string(v);
         return std::nullopt;
       }},
      {"--format",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         if (v != "ascii" && v != "binary") {
           return "must be ascii or binary";
         }
         o.encoding = v == "ascii" ? CloudEncoding::ascii : CloudEncoding::binary;
         return std::nullopt;
       }},
      {"--preview",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         o.preview_path = std::string(v);
         return std::nullopt;
       }},
      {"--render",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         o.render_path = std::string(v);
         return std::nullopt;
       }},
      {"--title",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         if (v.find_first_of("\r\n") != std::string_view::npos) return "must be one line";
         o.title = std::string(v);
         return std::nullopt;
       }},
      {"--render-colour",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         if (v != "height" && v != "intensity") {
           return "must be height or intensity";
         }
         o.render_colour = v == "height" ? cloud::RenderColour::height : cloud::RenderColour::intensity;
         return std::nullopt;
       }},
      {"--timeout",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto seconds = parse_double(v);
         // The upper bound keeps seconds * 1000 far inside a long long (a bigger value was
         // undefined behaviour in the conversion below).
         if (!seconds || !(*seconds > 0.0 && *seconds <= kMaxTimeoutSeconds)) {
           return "`" + std::string(v) + "` is not a number of seconds in (0, " +
                  std::to_string(static_cast<long long>(kMaxTimeoutSeconds)) + "]";
         }
         o.timeout = std::chrono::milliseconds(static_cast<long long>(std::ceil(*seconds * 1000.0)));
         return std::nullopt;
       }},
      {"--retries",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto value = base::parse_integer<std::uint32_t>(v);
         if (!value || *value > kMaxRetries) {
           return "`" + std::string(v) + "` is not a number of retries in 0.." + std::to_string(kMaxRetries);
         }
         o.retries = *value;
         return std::nullopt;
       }},
      {"--reconnect-attempts",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto value = base::parse_integer<std::uint32_t>(v);
         if (!value || *value < 1 || *value > kMaxReconnectAttempts) {
           return "`" + std::string(v) + "` is not a number of attempts in 1.." + std::to_string(kMaxReconnectAttempts);
         }
         o.reconnect.attempts = *value;
         o.reconnect_given = true;
         return std::nullopt;
       }},
      {"--reconnect-interval",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto seconds = parse_double(v);
         if (!seconds || !(*seconds >= 0.001 && *seconds <= kMaxReconnectIntervalSeconds)) {
           return "`" + std::string(v) + "` is not a number of seconds in 0.001..60";
         }
         o.reconnect.interval = std::chrono::milliseconds(static_cast<long long>(std::llround(*seconds * 1000.0)));
         o.reconnect.max_interval = std::max(o.reconnect.max_interval, o.reconnect.interval);
         o.reconnect_given = true;
         return std::nullopt;
       }},
      {"--reconnect-backoff",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto factor = parse_double(v);
         if (!factor || !(*factor >= 1.0 && *factor <= kMaxReconnectBackoff)) {
           return "`" + std::string(v) + "` is not a backoff factor in 1..10";
         }
         o.reconnect.backoff = *factor;
         o.reconnect_given = true;
         return std::nullopt;
       }},
      {"--optical-offset",
       [](ScanOptions& o, std::string_view v) -> std::optional<std::string> {
         const auto offset = parse_vector(v);
         if (!offset) {
           return "`" + std::string(v) + "` is not X,Y,Z in metres";
         }
         o.optical_offset_m = *offset;
         return std::nullopt;
       }},
  };
  return table;
}

// The last four characters in lower case (".ply", ".PNG" -> ".png"); empty when shorter.
std::string lower_extension(std::string_view path) {
  if (path.size() < 4) return {};
  std::string extension(path.substr(path.size() - 4));
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

bool ends_in_png(std::string_view path) { return lower_extension(path) == ".png"; }

std::optional<std::string> check_combination(const ScanOptions& options) {
  if (options.device.has_value() == options.hub.has_value()) {
    return "give either --device ENDPOINT or --hub HOST:PORT --hub-device NAME";
  }
  if (options.hub && options.hub_device.empty()) {
    return "--hub needs --hub-device NAME";
  }
  if (!options.hub && !options.hub_device.empty()) {
    return "--hub-device needs --hub";
  }
  if (options.hub && options.lpt) {
    return "--lpt is for --device; through a hub the hub drives the stepper";
  }
  if (options.hub && options.reconnect_given) {
    return "--reconnect-* are for --device; a hub reconnects to its devices itself";
  }
  if (options.out_path.empty()) {
    return "--out FILE.ply or FILE.pcd is required";
  }
  if (!output_format(options.out_path, options.encoding)) {
    return "--out: the file name must end in .ply or .pcd";
  }
  if (options.preview_path && !ends_in_png(*options.preview_path)) {
    return "--preview: the file name must end in .png";
  }
  if (options.render_path && !ends_in_png(*options.render_path)) {
    return "--render: the file name must end in .png";
  }
  return std::nullopt;
}

}  // namespace

OptionsResult parse_scan_options(const std::vector<std::string_view>& args) {
  ScanOptions options;
  base::CommandLine command_line("ldoem-scan");
  CLI::App& app = command_line.app();
  app.add_flag("--half-step", options.half_step);
  app.add_flag("--fit", options.fit);
  for (const auto& [name, option_setter] : setters()) {
    // A named reference for the lambda: clang before 16 cannot capture a structured binding.
    const Setter& setter = option_setter;
    base::take_text(app, std::string(name), [&options, &setter](const std::string& value) {
      return setter(options, value);
    });
  }
  if (auto problem = command_line.parse(args)) {
    return usage_error(*problem);
  }
  options.help = command_line.help_requested();
  options.help_all = command_line.help_all_requested();
  options.version = command_line.version_requested();
  if (options.version) return options;
  if (command_line.completion_requested()) {
    options.completion_script = command_line.completion_script();
  }
  if (options.help || options.help_all || options.completion_script) {
    return options;
  }
  if (auto problem = check_combination(options)) {
    return usage_error(*problem);
  }
  return options;
}

std::optional<cloud::CloudFileFormat> output_format(std::string_view path, CloudEncoding encoding) {
  const std::string extension = lower_extension(path);
  const bool ascii = encoding == CloudEncoding::ascii;
  if (extension == ".ply") {
    return ascii ? cloud::CloudFileFormat::ply_ascii : cloud::CloudFileFormat::ply_binary;
  }
  if (extension == ".pcd") {
    return ascii ? cloud::CloudFileFormat::pcd_ascii : cloud::CloudFileFormat::pcd_binary;
  }
  return std::nullopt;
}

base::Expected<AcquisitionPlan, std::string> make_plan(const ScanOptions& options) {
  auto sectors = plan_sectors(options.horizontal_apex_deg, options.horizontal_resolution_deg, options.speed_hz);
  if (!sectors) {
    return usage_error(sectors.error());
  }
  auto layers = plan_layers(options.vertical_apex_deg, options.vertical_resolution_deg, options.half_step);
  if (!layers) {
    return usage_error(layers.error());
  }
  if (options.device && !options.lpt && layers->layer_count > 1) {
    return usage_error("more than one layer needs --lpt ENDPOINT for the tilt stepper (or --vertical-apex 0)");
  }
  AcquisitionPlan plan;
  plan.sectors = std::move(sectors.value());
  plan.layers = layers.value();
  plan.motor_speed_hz = options.speed_hz;
  plan.step_rate_hz = options.step_rate_hz;
  plan.optical_offset_m = options.optical_offset_m;
  plan.profile_timeout = options.timeout;
  plan.retries = options.retries;
  return plan;
}

std::string scan_usage(std::string_view program) {
  std::string text = "usage: " + std::string(program) +
                     " (--device ENDPOINT [--lpt ENDPOINT] | --hub HOST:PORT --hub-device NAME) --out FILE [options]\n";
  text += R"(
3D acquisition (the paper's sequence): INITIALIZE, MOVEMOTOR to the low vertical apex, ROTATE,
MEASURE, then per layer GET2DPROFILE and MOVEMOTOR one layer step, IDLE, MOVEMOTOR home.
Points are written in the tilt pivot frame (x forward, y left, z up; D5).

Device:
  --device ENDPOINT            the scanner: can:IFACE[:REQ:RESP], tcp:HOST[:PORT],
                               serial:PATH[:BAUD] or serial:pty:PATH (docs/endpoints.md)
  --lpt ENDPOINT               the tilt stepper: lpt:pty:PATH, lpt:/dev/parportN, lpt:gpio:CHIP
                               (needed with --device when there is more than one layer)
  --hub HOST:PORT              go through ldoem-hub instead (its device drives the stepper)
  --hub-device NAME            the hub's device name
Geometry:
  --horizontal-apex DEG        measured sector, centred on +x (default 20)
  --horizontal-resolution DEG  head angle step, multiple of 0.125 (default 0.25)
  --vertical-apex DEG          tilt range, centred on level (default 21.6)
  --vertical-resolution DEG    tilt per layer: a whole number of 0.09 deg steps, or of
                               0.045 deg with --half-step (default 0.18)
  --optical-offset X,Y,Z       optical centre from the tilt pivot, metres (default 0,0,0)
  --speed HZ                   head speed 5..20 (default 10)
  --half-step                  drive the stepper in half steps (default full steps)
  --step-rate HZ               stepper pulse rate, 1..20000 (default 200)
Output:
  --out FILE                   .ply or .pcd (required)
  --format ascii|binary        (default binary)
  --preview FILE.png           range image as seen from the scanner (top row = highest layer)
  --render FILE.png            perspective view of the cloud, 1600x1000, from behind and above
                               the scanner
  --render-colour height|intensity   what the render's colours show (default height)
  --title TEXT                 the render's title (e.g. the scene); scanner and settings follow
  --fit                        fit the wall plane and a cylinder; print diameter, length and
                               wall distance
  --timeout SECONDS            wait for each profile (default 5)
  --retries N                  after a retryable fault (a timeout, a corrupted reply, a lost
                               connection) try the step again up to N times (default 3, 0..100);
                               a lost connection or a device reset is reconnected and configured
                               again first; a device fault (motor nibble, ERROR) is final
  --reconnect-attempts N       reopen a lost connection at most N times (default 10, 1..1000)
  --reconnect-interval SECONDS the first pause between two attempts (default 0.5, 0.001..60)
  --reconnect-backoff F        each next pause F times the last, at most 30 s or the interval
                               (default 1: evenly spaced; 1..10)
  --help                       the most used options
  --help-all                   this text
  --version                    print the name and version
  --completion bash            print a bash completion

The cloud is written to a temporary file beside FILE and renamed only when complete: a failed
scan leaves no partial cloud under FILE.

Exit codes: 0 scan written, 1 device or file failure (a final fault, or retries used up; the
message names it), 2 usage error or impossible plan,
128+N after signal N (SIGINT, SIGTERM; the scanner is sent to IDLE and the tilt home first).

Examples:
  ldoem-scan --device can:vcan0 --lpt lpt:pty:/tmp/ldoem-lpt --out scan.ply
  ldoem-scan --device tcp:127.0.0.1:49152 --lpt lpt:pty:/tmp/ldoem-lpt --out scan.pcd \
             --format ascii --preview scan.png --fit
  ldoem-scan --hub 127.0.0.1:49200 --hub-device left --half-step --vertical-resolution 0.045 \
             --out scan.ply
)";
  return text;
}

std::string scan_brief_usage(std::string_view program) {
  return base::brief_help(program, scan_usage(program), "Take a 3D scan with an LD-OEM and its tilt stepper; write a .ply or .pcd cloud.",
                          {"--device", "--lpt", "--hub", "--hub-device", "--out", "--horizontal-apex", "--vertical-apex",
                           "--vertical-resolution", "--speed", "--format", "--preview", "--render", "--fit", "--timeout",
                           "--help", "--version"});
}

}  // namespace ldoem::scan
