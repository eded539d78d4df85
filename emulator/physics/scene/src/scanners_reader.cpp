#include "scanners_reader.hpp"

#include "ldoem/base/device_constants.hpp"
#include "ldoem/base/endpoint.hpp"
#include "scanner_reader.hpp"

#include <map>
#include <set>

namespace ldoem::scene::detail {
namespace {

constexpr std::uint16_t kFirstCanRequestId = 0x6C0;  // D1; scanner k: 0x6C0 + 2k / 0x6C1 + 2k
constexpr unsigned kMaxCanId = 0x7FF;                // 11-bit (D1)

// One endpoint of the scanner, in the grammar of the daemon's options (base/endpoint.hpp,
// docs/endpoints.md): the scene offers what the daemon would offer.
base::Endpoint read_endpoint(const std::string& file, const YAML::Node& node, const std::string& path,
                             base::EndpointExpect expect) {
  const std::string text = read_string(file, node, path);
  auto endpoint = base::parse_endpoint(text, base::EndpointUse{base::EndpointSide::offer, expect});
  if (!endpoint) {
    const base::EndpointError& error = endpoint.error();
    const SceneErrorKind kind = error.kind == base::EndpointErrorKind::out_of_range ? SceneErrorKind::out_of_range
                                                                                    : SceneErrorKind::wrong_type;
    fail(file, kind, node, path, base::describe(error));
  }
  return std::move(endpoint).value();
}

ScannerEndpoints read_endpoints(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  ScannerEndpoints endpoints;
  if (auto ids = map.get("can_ids")) {
    // The key before the grammar: name the new one rather than "unknown key".
    const std::string text = read_string(file, *ids, map.child_path("can_ids"));
    fail(file, SceneErrorKind::unknown_key, *ids, map.child_path("can_ids"),
         "can_ids is the old key; write can: can:IF:" + text + " (IF: the daemon's --can, docs/endpoints.md)");
  }
  if (auto tcp = map.get("tcp")) {
    const auto endpoint = std::get<base::TcpEndpoint>(read_endpoint(file, *tcp, map.child_path("tcp"), base::EndpointExpect::tcp));
    endpoints.tcp = TcpEndpointConfig{endpoint.host, endpoint.port};
  }
  if (auto can = map.get("can")) {
    const auto endpoint = std::get<base::CanEndpoint>(read_endpoint(file, *can, map.child_path("can"), base::EndpointExpect::can));
    if (!endpoint.ids_given) {
      fail(file, SceneErrorKind::wrong_type, *can, map.child_path("can"),
           "a scanner's can: endpoint names its ids, e.g. can:vcan0:6C2:6C3 (without: its flash's)");
    }
    endpoints.can_ids = std::array<std::uint16_t, 2>{static_cast<std::uint16_t>(endpoint.request_id),
                                                     static_cast<std::uint16_t>(endpoint.response_id)};
    endpoints.can_interface = endpoint.interface;
  }
  if (auto serial = map.get("serial")) {
    endpoints.serial_pty =
        std::get<base::SerialEndpoint>(read_endpoint(file, *serial, map.child_path("serial"), base::EndpointExpect::serial)).path;
  }
  if (auto lpt = map.get("lpt")) {
    const auto endpoint = std::get<base::LptEndpoint>(read_endpoint(file, *lpt, map.child_path("lpt"), base::EndpointExpect::lpt));
    endpoints.lpt = LptEndpointConfig{endpoint.backend == base::LptBackend::gpio, endpoint.target};
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
    const YAML::Node ids_node = ids_in_endpoints ? node["endpoints"]["can"] : node;
    const std::string ids_path = ids_in_endpoints ? path + ".endpoints.can" : path + ".flash.can_request_id";
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
