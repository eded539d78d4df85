#include "scanners_reader.hpp"

#include "ldoem/base/device_constants.hpp"
#include "scanner_reader.hpp"

#include <charconv>
#include <map>
#include <set>

namespace ldoem::scene::detail {
namespace {

constexpr std::uint16_t kFirstCanRequestId = 0x6C0;  // D1; scanner k: 0x6C0 + 2k / 0x6C1 + 2k
constexpr unsigned kMaxCanId = 0x7FF;                // 11-bit (D1)
constexpr std::string_view kLoopback = "127.0.0.1";

bool all_digits(std::string_view text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
}

std::optional<unsigned> parse_number(std::string_view text, int base) {
  unsigned value = 0;
  const auto [end, status] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (status != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return value;
}

// "HOST:PORT", "HOST" (port 49152) or a bare port number (on 127.0.0.1), as --tcp.
TcpEndpointConfig read_tcp(const std::string& file, const YAML::Node& node, const std::string& path) {
  const std::string text = read_string(file, node, path);
  const std::string_view view(text);
  const auto colon = view.rfind(':');
  TcpEndpointConfig tcp{std::string(kLoopback), base::kHostTcpPort};  // spec 4.1, as --tcp HOST
  std::string_view port_text;
  if (all_digits(view)) {
    port_text = view;
  } else {
    tcp.address = std::string(view.substr(0, colon));
    if (colon != std::string_view::npos) port_text = view.substr(colon + 1);
    if (tcp.address.empty() || (colon != std::string_view::npos && port_text.empty())) {
      fail(file, SceneErrorKind::wrong_type, node, path, "expects HOST[:PORT] or a port, e.g. 127.0.0.1:49153");
    }
  }
  if (!port_text.empty()) {
    const auto port = parse_number(port_text, 10);
    if (!port || *port > 0xFFFF) fail(file, SceneErrorKind::out_of_range, node, path, "port must be 0..65535 (0: any free port)");
    tcp.port = static_cast<std::uint16_t>(*port);
  }
  return tcp;
}

std::optional<std::uint16_t> parse_can_id(std::string_view text) {
  if (text.starts_with("0x") || text.starts_with("0X")) text.remove_prefix(2);
  const auto id = parse_number(text, 16);
  if (!id || *id > kMaxCanId) return std::nullopt;
  return static_cast<std::uint16_t>(*id);
}

// "REQUEST:RESPONSE" in hex, as --can-ids.
std::array<std::uint16_t, 2> read_can_ids(const std::string& file, const YAML::Node& node, const std::string& path) {
  const std::string text = read_string(file, node, path);
  const auto colon = text.find(':');
  if (colon == std::string::npos) fail(file, SceneErrorKind::wrong_type, node, path, "expects REQUEST:RESPONSE in hex, e.g. 6C2:6C3");
  const auto request = parse_can_id(std::string_view(text).substr(0, colon));
  const auto response = parse_can_id(std::string_view(text).substr(colon + 1));
  if (!request || !response) fail(file, SceneErrorKind::out_of_range, node, path, "identifiers are 11-bit hex values 000..7FF (D1)");
  if (*request == *response) fail(file, SceneErrorKind::conflicting_keys, node, path, "request and response identifiers must differ");
  return {*request, *response};
}

// "pty:PATH" (serial and LPT) or "gpio:CHIP" (LPT only).
std::pair<std::string, std::string> read_backend(const std::string& file, const YAML::Node& node, const std::string& path,
                                                 bool gpio_allowed) {
  const std::string text = read_string(file, node, path);
  const auto colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  const std::string target = colon == std::string::npos ? std::string() : text.substr(colon + 1);
  if (target.empty() || (kind != "pty" && !(gpio_allowed && kind == "gpio"))) {
    fail(file, SceneErrorKind::wrong_type, node, path, gpio_allowed ? "expects pty:PATH or gpio:CHIP" : "expects pty:PATH");
  }
  return {kind, target};
}

ScannerEndpoints read_endpoints(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  ScannerEndpoints endpoints;
  if (auto tcp = map.get("tcp")) endpoints.tcp = read_tcp(file, *tcp, map.child_path("tcp"));
  if (auto ids = map.get("can_ids")) endpoints.can_ids = read_can_ids(file, *ids, map.child_path("can_ids"));
  if (auto serial = map.get("serial")) endpoints.serial_pty = read_backend(file, *serial, map.child_path("serial"), false).second;
  if (auto lpt = map.get("lpt")) {
    auto [kind, target] = read_backend(file, *lpt, map.child_path("lpt"), true);
    endpoints.lpt = LptEndpointConfig{kind == "gpio", std::move(target)};
  }
  map.finish();
  return endpoints;
}

void check_name(const std::string& file, const YAML::Node& node, const std::string& path, const std::string& name) {
  // Names appear in file names (<scene>.<name>.flash) and in the daemon's output lines.
  const bool plain = !name.empty() && name.size() <= 64 &&
                     name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") ==
                         std::string::npos;
  if (!plain) fail(file, SceneErrorKind::out_of_range, node, path, "a name is 1..64 letters, digits, '_' or '-'");
}

ScannerEntry read_entry(const std::string& file, const YAML::Node& node, std::size_t index, const EffectSet& scene_effects) {
  const std::string path = "scanners[" + std::to_string(index) + "]";
  MapReader map(file, node, path);
  ScannerEntry entry;
  const YAML::Node name_node = map.require("name");
  entry.name = read_string(file, name_node, map.child_path("name"));
  check_name(file, name_node, map.child_path("name"), entry.name);
  entry.effects = scene_effects;
  if (auto effects = map.get("effects")) entry.effects = read_effects(file, *effects, map.child_path("effects"));
  if (auto flash_file = map.get("flash_file")) {
    entry.flash_file = read_string(file, *flash_file, map.child_path("flash_file"));
    if (entry.flash_file->empty()) fail(file, SceneErrorKind::out_of_range, *flash_file, map.child_path("flash_file"), "must not be empty");
  }
  if (auto endpoints = map.get("endpoints")) entry.endpoints = read_endpoints(file, *endpoints, map.child_path("endpoints"));
  entry.config = read_scanner_fields(map);
  // Scanner k answers on 0x6C0 + 2k / 0x6C1 + 2k unless its flash names its identifiers
  // (docs/scaling.md's plan for one shared bus); the first keeps D1's defaults.
  const std::optional<YAML::Node> flash = map.get("flash");  // read already; asking again changes nothing
  const bool flash_names_ids = flash && flash->IsMap() && (flash->operator[]("can_request_id").IsDefined() ||
                                                           flash->operator[]("can_response_id").IsDefined());
  if (!flash_names_ids) {
    const auto offset = static_cast<std::uint16_t>(2 * index);
    if (static_cast<unsigned>(kFirstCanRequestId + offset + 1) > kMaxCanId) {
      fail(file, SceneErrorKind::out_of_range, node, map.child_path("flash"),
           "too many scanners for the default CAN identifier plan: give flash.can_request_id and can_response_id");
    }
    entry.config.flash.can_request_id = static_cast<std::uint16_t>(kFirstCanRequestId + offset);
    entry.config.flash.can_response_id = static_cast<std::uint16_t>(kFirstCanRequestId + offset + 1);
  }
  check_fog_returns(file, node, path, entry.config, entry.effects);
  map.finish();
  return entry;
}

// Remembers who claimed a value first; a second claim is a located error naming the first.
template <class Key>
class Claims {
 public:
  Claims(const std::string& file, std::string what) : file_(file), what_(std::move(what)) {}
  void claim(const Key& key, const std::string& owner, const YAML::Node& at, const std::string& path) {
    const auto [found, inserted] = owners_.emplace(key, owner);
    if (!inserted) fail(file_, SceneErrorKind::conflicting_keys, at, path, what_ + " already used by scanner '" + found->second + "'");
  }

 private:
  const std::string& file_;
  std::string what_;
  std::map<Key, std::string> owners_;
};

void check_unique(const std::string& file, const YAML::Node& list, const std::vector<ScannerEntry>& entries) {
  std::set<std::string> names;
  Claims<std::uint16_t> ports(file, "this TCP port is");
  Claims<std::uint16_t> can_ids(file, "this CAN identifier is");
  Claims<std::string> ptys(file, "this pty path is");
  Claims<std::string> flash_files(file, "this flash file is");
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const ScannerEntry& entry = entries[i];
    const YAML::Node node = list[i];
    const std::string path = "scanners[" + std::to_string(i) + "]";
    if (!names.insert(entry.name).second) {
      fail(file, SceneErrorKind::duplicate_key, node["name"], path + ".name", "scanner name '" + entry.name + "' given twice");
    }
    const ScannerEndpoints& endpoints = entry.endpoints;
    if (endpoints.tcp && endpoints.tcp->port != 0) {
      ports.claim(endpoints.tcp->port, entry.name, node["endpoints"]["tcp"], path + ".endpoints.tcp");
    }
    const bool ids_in_endpoints = endpoints.can_ids.has_value();
    const std::array<std::uint16_t, 2> ids =
        ids_in_endpoints ? *endpoints.can_ids
                         : std::array<std::uint16_t, 2>{entry.config.flash.can_request_id, entry.config.flash.can_response_id};
    const YAML::Node ids_node = ids_in_endpoints ? node["endpoints"]["can_ids"] : node;
    const std::string ids_path = ids_in_endpoints ? path + ".endpoints.can_ids" : path + ".flash.can_request_id";
    for (const std::uint16_t id : ids) can_ids.claim(id, entry.name, ids_node, ids_path);
    if (endpoints.serial_pty) ptys.claim(*endpoints.serial_pty, entry.name, node["endpoints"]["serial"], path + ".endpoints.serial");
    if (endpoints.lpt && !endpoints.lpt->gpio) {
      ptys.claim(endpoints.lpt->target, entry.name, node["endpoints"]["lpt"], path + ".endpoints.lpt");
    }
    if (entry.flash_file) flash_files.claim(*entry.flash_file, entry.name, node["flash_file"], path + ".flash_file");
  }
}

}  // namespace

void check_fog_returns(const std::string& file, const YAML::Node& section, const std::string& path,
                       const ScannerConfig& scanner, const EffectSet& effects) {
  // Fog's returns are a pulse in the received waveform, attenuated like every other.
  const bool fog_can_return = effects.has(Effect::waveform) && effects.has(Effect::atmosphere);
  if (scanner.atmosphere.fog_returns && !fog_can_return) {
    fail(file, SceneErrorKind::conflicting_keys, section["atmosphere"]["fog_returns"], path + ".atmosphere.fog_returns",
         "fog's returns are pulses in the received waveform: name the effects waveform and atmosphere");
  }
}

std::vector<ScannerEntry> read_scanners(const std::string& file, const YAML::Node& node, const EffectSet& scene_effects) {
  require_sequence(file, node, "scanners");
  if (node.size() == 0) fail(file, SceneErrorKind::out_of_range, node, "scanners", "needs at least one scanner");
  if (node.size() > kMaxSceneScanners) {
    fail(file, SceneErrorKind::out_of_range, node, "scanners", "more than " + std::to_string(kMaxSceneScanners) + " scanners");
  }
  std::vector<ScannerEntry> entries;
  entries.reserve(node.size());
  for (std::size_t i = 0; i < node.size(); ++i) entries.push_back(read_entry(file, node[i], i, scene_effects));
  check_unique(file, node, entries);
  return entries;
}

}  // namespace ldoem::scene::detail
