// Issue 15: several scanners in one ldoem-emud. Each scanner's endpoints and flash from the
// scene (scanner_options), and a two-scanner daemon over TCP: both clouds right, each scanner
// sees the other's housing where it stands and never its own.
#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/daemon/scanner_options.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/text.hpp"
#include "ldoem/scene/scene.hpp"
#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

scene::Scene load(const std::string& yaml) {
  auto scene = scene::load_scene_from_string(yaml, "dir/cell.yaml");
  EXPECT_TRUE(scene.has_value()) << (scene ? "" : scene.error().message());
  return scene ? *scene : scene::Scene{};
}

Options parsed(std::vector<std::string_view> arguments) {
  const auto command = parse_command_line(arguments);
  EXPECT_TRUE(command.has_value()) << (command ? "" : command.error().message);
  return command ? command->options : Options{};
}

const char* const kTwoScannersYaml =
    "scanners:\n"
    "  - {name: left, endpoints: {tcp: \"tcp:127.0.0.1:0\", serial: \"serial:pty:/tmp/l\"}, flash_file: left.img}\n"
    "  - {name: right, endpoints: {tcp: \"tcp:127.0.0.1:40002\", can: \"can:vcan0:6D0:6D1\", lpt: \"lpt:gpio:chip1\"}}\n";

TEST(ScannerOptions, OneScannerKeepsTheCommandLine) {
  const Options options = parsed({"--scene", "dir/cell.yaml", "--no-can", "--tcp", "tcp:127.0.0.1:0"});
  const auto all = scanner_options(options, load("scanner: {}"));
  ASSERT_TRUE(all.has_value());
  ASSERT_EQ(all->size(), 1u);
  EXPECT_EQ((*all)[0], options);
}

TEST(ScannerOptions, AOneEntryListFillsInWhatTheCommandLineLeavesOut) {
  const scene::Scene scene = load("scanners:\n  - {name: a, endpoints: {tcp: \"tcp:127.0.0.1:40001\", serial: \"serial:pty:/tmp/s\"}, flash_file: a.img}\n");
  const auto filled = scanner_options(parsed({"--scene", "dir/cell.yaml", "--no-can"}), scene);
  ASSERT_TRUE(filled.has_value()) << filled.error().message;
  EXPECT_EQ((*filled)[0].tcp, (TcpOption{"127.0.0.1", 40001}));
  EXPECT_EQ((*filled)[0].serial_pty, std::filesystem::path("/tmp/s"));
  EXPECT_EQ((*filled)[0].flash_path, default_flash_folder() / "a.img");  // never beside the scene
  // The command line wins over the scene.
  const auto given =
      scanner_options(parsed({"--scene", "dir/cell.yaml", "--no-can", "--tcp", "tcp:h:5", "--flash", "f"}), scene);
  ASSERT_TRUE(given.has_value());
  EXPECT_EQ((*given)[0].tcp, (TcpOption{"h", 5}));
  EXPECT_EQ((*given)[0].flash_path, std::filesystem::path("f"));
}

TEST(ScannerOptions, SeveralScannersTakeTheirEndpointsFromTheScene) {
  const auto all = scanner_options(parsed({"--scene", "dir/cell.yaml", "--can", "can:vcan0"}), load(kTwoScannersYaml));
  ASSERT_TRUE(all.has_value()) << all.error().message;
  ASSERT_EQ(all->size(), 2u);
  const Options& left = (*all)[0];
  const Options& right = (*all)[1];
  EXPECT_EQ(left.can_interface, std::optional<std::string>("vcan0"));  // one bus for all
  EXPECT_EQ(right.can_interface, std::optional<std::string>("vcan0"));
  EXPECT_TRUE(left.can_id_pairs.empty());  // its flash's: 6C0:6C1
  ASSERT_EQ(right.can_id_pairs.size(), 1u);
  EXPECT_EQ(right.can_id_pairs[0].request_id, 0x6D0);
  EXPECT_EQ(left.tcp, (TcpOption{"127.0.0.1", 0}));
  EXPECT_EQ(right.tcp, (TcpOption{"127.0.0.1", 40002}));
  EXPECT_EQ(left.serial_pty, std::filesystem::path("/tmp/l"));
  EXPECT_EQ(right.lpt, (LptOption{LptBackend::gpio, "chip1"}));
  EXPECT_EQ(left.flash_path, default_flash_folder() / "left.img");
  EXPECT_EQ(right.flash_path, default_flash_folder() / "cell.yaml.right.flash");
  const auto memory = scanner_options(parsed({"--scene", "dir/cell.yaml", "--no-flash"}), load(kTwoScannersYaml));
  ASSERT_TRUE(memory.has_value());
  EXPECT_TRUE((*memory)[1].flash_path.empty());
}

// The daemon has one bus: a scanner's can: endpoint on another interface is an error naming both.
TEST(ScannerOptions, ACanEndpointOnAnotherBusIsRefused) {
  const auto other = scanner_options(parsed({"--scene", "dir/cell.yaml", "--can", "can:vcan1"}), load(kTwoScannersYaml));
  ASSERT_FALSE(other.has_value());
  EXPECT_EQ(other.error().message,
            "scanners[1].endpoints.can: names vcan0 but the daemon's bus is --can can:vcan1 (one bus for all scanners)");
}

TEST(ScannerOptions, FlashDir_HoldsEveryScannersFlashUnderItsUsualName) {
  const auto all = scanner_options(parsed({"--scene", "dir/cell.yaml", "--no-can", "--flash-dir", "/state"}),
                                   load(kTwoScannersYaml));
  ASSERT_TRUE(all.has_value()) << all.error().message;  // not the refused --flash
  EXPECT_EQ((*all)[0].flash_path, std::filesystem::path("/state/left.img"));
  EXPECT_EQ((*all)[1].flash_path, std::filesystem::path("/state/cell.yaml.right.flash"));
  const auto absolute = scanner_options(parsed({"--scene", "dir/cell.yaml", "--no-can", "--flash-dir", "/state"}),
                                        load("scanners:\n  - {name: a, flash_file: /abs/a.img, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"
                                             "  - {name: b, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"));
  ASSERT_TRUE(absolute.has_value()) << absolute.error().message;
  EXPECT_EQ((*absolute)[0].flash_path, std::filesystem::path("/abs/a.img"));
  const auto one = scanner_options(parsed({"--scene", "dir/cell.yaml", "--no-can", "--flash-dir", "/state"}),
                                   load("scanners:\n  - {name: a, flash_file: a.img, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"));
  ASSERT_TRUE(one.has_value()) << one.error().message;
  EXPECT_EQ((*one)[0].flash_path, std::filesystem::path("/state/a.img"));
}

TEST(ScannerOptions, SeveralScannersRefuseOneDevicesOptions) {
  const scene::Scene scene = load(kTwoScannersYaml);
  const std::vector<std::pair<std::vector<std::string_view>, std::string>> cases{
      {{"--tcp", "tcp:h:1"}, "--tcp: names one scanner's endpoint"},
      {{"--can", "can:vcan0:6C0:6C1"}, "--can can:IF:REQ:RESP: names one scanner's endpoint"},
      {{"--serial", "serial:pty:/tmp/x"}, "--serial: names one scanner's endpoint"},
      {{"--lpt", "lpt:pty:/tmp/x"}, "--lpt: names one scanner's endpoint"},
      {{"--flash", "f"}, "--flash: with several scanners"},
      {{"--record", "r.pcapng"}, "--record: records one scanner"},
  };
  for (const auto& [extra, message] : cases) {
    std::vector<std::string_view> arguments{"--scene", "dir/cell.yaml"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto all = scanner_options(parsed(arguments), scene);
    ASSERT_FALSE(all.has_value()) << message;
    EXPECT_EQ(all.error().message.rfind(message, 0), 0u) << all.error().message;
  }
}

// Two scanners 3 m apart on the x axis, facing each other (right is turned by 180 deg), between
// two side walls at y = +-2 m and end walls at x = -3 m and x = 6 m. No effects: exact ranges.
constexpr double kApart_m = 3.0;
constexpr double kHousingRadius_m = 0.06;  // HousingConfig's default
const char* const kFacingYaml =
    "scanners:\n"
    "  - {name: left, pivot_pose: {position_m: [0, 0, 0]}, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"
    "  - {name: right, pivot_pose: {position_m: [3, 0, 0], rpy_deg: [0, 0, 180]}, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"
    "objects:\n"
    "  - {name: north, box: {size_m: [20, 0.2, 6]}, pose: {position_m: [1.5, 2.1, 0]}}\n"
    "  - {name: south, box: {size_m: [20, 0.2, 6]}, pose: {position_m: [1.5, -2.1, 0]}}\n"
    "  - {name: east, box: {size_m: [0.2, 20, 6]}, pose: {position_m: [6.1, 0, 0]}}\n"
    "  - {name: west, box: {size_m: [0.2, 20, 6]}, pose: {position_m: [-3.1, 0, 0]}}\n";

// "scanner left" / "tcp 127.0.0.1:P" lines -> name -> port.
std::map<std::string, std::uint16_t> ports_by_scanner(const std::string& stdout_text) {
  std::map<std::string, std::uint16_t> ports;
  std::istringstream lines(stdout_text);
  std::string line;
  std::string current;
  while (std::getline(lines, line)) {
    if (line.rfind("scanner ", 0) == 0) current = line.substr(8);
    if (line.rfind("tcp ", 0) == 0) ports[current] = static_cast<std::uint16_t>(std::stoi(line.substr(line.rfind(':') + 1)));
  }
  return ports;
}

std::string exchange(TcpHost& host, std::string_view request_text) {
  host.send(telegram(request_text));
  const auto frame = host.next_frame();
  return frame ? to_hex(*frame) : std::string("(no reply)");
}

std::optional<protocol::Profile> one_profile(TcpHost& host) {
  host.send(telegram("GET_PROFILE 0001 39ff"));
  const auto payload = host.next_payload();
  if (!payload) return std::nullopt;
  auto profile = protocol::decode_profile(*payload);
  EXPECT_TRUE(profile) << to_hex(*payload);
  if (!profile) return std::nullopt;
  return *profile;
}

// DISTANCE at a head angle in 1/16 deg, if the profile measured it.
std::optional<double> range_at(const protocol::Profile& profile, unsigned ticks) {
  for (const auto& sector : profile.sectors) {
    for (std::size_t i = 0; i < sector.points.size(); ++i) {
      if ((sector.start_dir_ticks + i * sector.dir_step_ticks) % 5760 == ticks) return sector.points[i].distance_q8_m / 256.0;
    }
  }
  return std::nullopt;
}

constexpr double kQuantum_m = 1.0 / 256.0;  // DISTANCE (spec 2.3)

TEST(DaemonScanners, TwoScannersOverTcp_EachSeesTheOthersHousingAndNotItsOwn) {
  TempDir dir;
  const std::string scene = dir.write("facing.yaml", kFacingYaml);
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--no-flash", "--virtual-time", "--timeout", "120"});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  const auto ports = ports_by_scanner(process->stdout_text());
  ASSERT_EQ(ports.size(), 2u) << process->stdout_text();
  ASSERT_NE(ports.at("left"), ports.at("right"));

  std::map<std::string, protocol::Profile> profiles;
  for (const auto& [name, port] : ports) {
    auto host = TcpHost::connect(port);
    ASSERT_TRUE(host);
    exchange(*host, "TRANS_ROTATE 000A");
    exchange(*host, "TRANS_MEASURE");
    auto profile = one_profile(*host);
    ASSERT_TRUE(profile) << name;
    profiles.emplace(name, *profile);
  }
  for (const auto& [name, profile] : profiles) {
    SCOPED_TRACE(name);
    // Toward the other scanner (head angle 0: each faces the other): its housing, 3 m minus
    // the housing's radius, where the end wall (6 m or 3 m behind it) would be without it.
    const auto toward_other = range_at(profile, 0);
    ASSERT_TRUE(toward_other);
    EXPECT_NEAR(*toward_other, kApart_m - kHousingRadius_m, kQuantum_m);
    // Sideways: the side walls 2 m away. A scanner that saw its own housing would measure
    // nothing (every beam would stop 6 cm out, inside D_min).
    const auto left_of = range_at(profile, 1440);   // 90 deg
    const auto right_of = range_at(profile, 4320);  // 270 deg
    ASSERT_TRUE(left_of && right_of);
    EXPECT_NEAR(*left_of, 2.0, kQuantum_m);
    EXPECT_NEAR(*right_of, 2.0, kQuantum_m);
    // 30 deg off the axis the beam misses the housing and meets the side wall: 2 / sin 30 = 4 m.
    const auto off_axis = range_at(profile, 480);
    ASSERT_TRUE(off_axis);
    EXPECT_NEAR(*off_axis, 4.0, kQuantum_m);
  }
}

TEST(DaemonScanners, OneEntryListStreamsTheSameBytesAsTheScannerSection) {
  TempDir dir;
  const std::string body =
      "seed: 5\neffects: [noise, intensity, incidence]\n"
      "objects:\n  - {name: wall, box: {size_m: [0.2, 20, 6]}, pose: {position_m: [5.1, 0, 0]}, reflectance: 0.4}\n";
  const std::string single = dir.write("single.yaml", body + "scanner: {pivot_pose: {position_m: [0, 0.3, 0.1]}}\n");
  const std::string listed =
      dir.write("listed.yaml", body + "scanners:\n  - {name: only, pivot_pose: {position_m: [0, 0.3, 0.1]}}\n");
  std::vector<std::string> frames;
  for (const std::string& scene : {single, listed}) {
    auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--no-flash", "--virtual-time", "--tcp",
                                         "tcp:127.0.0.1:0", "--timeout", "120"});
    ASSERT_TRUE(process);
    ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
    EXPECT_EQ(process->stdout_text().find("scanner "), std::string::npos);  // one scanner: lines as before
    auto host = TcpHost::connect(process->tcp_port());
    ASSERT_TRUE(host);
    exchange(*host, "TRANS_ROTATE 000A");
    exchange(*host, "TRANS_MEASURE");
    std::string all;
    for (int i = 0; i < 3; ++i) {
      host->send(telegram("GET_PROFILE 0001 39ff"));
      const auto frame = host->next_frame();
      ASSERT_TRUE(frame);
      all += to_hex(*frame);
    }
    frames.push_back(all);
  }
  EXPECT_EQ(frames[0], frames[1]);
}

TEST(DaemonScanners, AScannerWithoutHostTransport_ExitsTwoNamingIt) {
  TempDir dir;
  const std::string scene = dir.write("cell.yaml", "scanners:\n  - {name: a, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n  - {name: b}\n");
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--no-flash"});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  EXPECT_NE(process->stderr_text().find("scanners[1] (b): no host transport"), std::string::npos) << process->stderr_text();
  const std::string single = dir.write("single.yaml", "scanner: {}\n");
  auto alone = DaemonProcess::start({"--scene", single, "--no-can", "--no-flash"});
  ASSERT_TRUE(alone);
  EXPECT_EQ(alone->wait(), std::optional<int>(2));
  EXPECT_NE(alone->stderr_text().find("--no-can: no host transport left (add --tcp or --serial)"), std::string::npos)
      << alone->stderr_text();
}

TEST(DaemonScanners, SeveralScannersWithADevicesOption_ExitTwoWithOneLine) {
  TempDir dir;
  const std::string scene = dir.write("facing.yaml", kFacingYaml);
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash"});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  EXPECT_NE(process->stderr_text().find("--tcp: names one scanner's endpoint; with 2 scanners"), std::string::npos)
      << process->stderr_text();
}

// What ldoem-emud-group@.service runs: the scene read-only, every scanner's flash in the state
// directory (--flash-dir), saved there on SIGTERM (exit 143) and nothing beside the scene.
TEST(DaemonScanners, FlashDir_SigtermSavesEveryScannersFlashThere) {
  TempDir dir;
  const std::string scene =
      dir.write("cell.yaml", "scanners:\n  - {name: a, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"
                             "  - {name: b, flash_file: b.img, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n");
  const std::filesystem::path state = dir.path("state");
  std::filesystem::create_directory(state);
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--flash-dir", state.string()});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  process->signal(SIGTERM);
  EXPECT_EQ(process->wait(), std::optional<int>(128 + SIGTERM)) << process->stderr_text();
  for (const char* name : {"cell.yaml.a.flash", "b.img"}) {
    std::ifstream image(state / name);
    std::string first_line;
    std::getline(image, first_line);
    EXPECT_EQ(first_line, "ldoem-flash 1") << name;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path("cell.yaml.a.flash")));
  EXPECT_FALSE(std::filesystem::exists(dir.path("b.img")));
}

TEST(DaemonScanners, FlashDirThatIsNoFolder_ExitsTwoBeforeStarting) {
  TempDir dir;
  const std::string scene = dir.write("cell.yaml", "scanner: {}\n");
  auto process = DaemonProcess::start(
      {"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--flash-dir", dir.path("missing")});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  EXPECT_NE(process->stderr_text().find("--flash-dir " + dir.path("missing") + ": not a folder"), std::string::npos)
      << process->stderr_text();
}

TEST(DaemonScanners, FlashInAFolderThatDoesNotExist_ExitsTwoBeforeStarting) {
  TempDir dir;
  const std::string scene = dir.write("cell.yaml", "scanner: {}\n");
  const std::string flash = dir.path("missing") + "/cell.flash";
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--flash", flash});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  EXPECT_NE(process->stderr_text().find("--flash " + flash + ": the folder " + dir.path("missing") + " does not exist"),
            std::string::npos)
      << process->stderr_text();
}

// Issue 11, no data lost: a flash that cannot be saved at exit is exit 1 with a line naming the
// file and the OS error, not a clean stop. We run as root, so the folder is taken away instead
// of made read-only.
TEST(DaemonScanners, FlashFolderRemovedWhileRunning_SigtermExitsOneNamingTheFile) {
  TempDir dir;
  const std::string scene = dir.write("cell.yaml", "scanner: {}\n");
  const std::filesystem::path state = dir.path("state");
  std::filesystem::create_directory(state);
  const std::string flash = (state / "cell.flash").string();
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--flash", flash});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  std::filesystem::remove_all(state);
  process->signal(SIGTERM);
  EXPECT_EQ(process->wait(), std::optional<int>(1)) << process->stderr_text();
  EXPECT_NE(process->stderr_text().find("error: flash " + flash + " not saved: mkstemp: No such file or directory"),
            std::string::npos)
      << process->stderr_text();
}

// One scanner's folder replaced by a file: its flash is lost (exit 1), the next one's is saved.
TEST(DaemonScanners, OneScannersFlashFolderReplacedByAFile_TheOthersIsStillSaved) {
  TempDir dir;
  const std::string scene = dir.write("cell.yaml", "scanners:\n  - {name: a, flash_file: gone/a.img, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n"
                                                   "  - {name: b, flash_file: b.img, endpoints: {tcp: \"tcp:127.0.0.1:0\"}}\n");
  const std::filesystem::path gone = dir.path("gone");
  std::filesystem::create_directory(gone);
  auto process = DaemonProcess::start({"--scene", scene, "--no-can", "--flash-dir", dir.path("")});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  std::filesystem::remove_all(gone);
  std::ofstream(gone) << "a file where the folder was\n";
  ASSERT_FALSE(std::filesystem::exists(dir.path("b.img")));  // nothing written before exit
  process->signal(SIGTERM);
  EXPECT_EQ(process->wait(), std::optional<int>(1)) << process->stderr_text();
  EXPECT_NE(process->stderr_text().find("flash " + (gone / "a.img").string() + " not saved: mkstemp: Not a directory"),
            std::string::npos)
      << process->stderr_text();
  std::ifstream saved(dir.path("b.img"));
  std::string first_line;
  std::getline(saved, first_line);
  EXPECT_EQ(first_line, "ldoem-flash 1");
}

// L-flash-1: with the flash's folder gone, a host's flash write is answered as the service's
// error (SET_FILTER, which has none: SERVICE_FAILURE reason 6), never as a success, and the
// device keeps what it had.
TEST(DaemonScanners, FlashFolderRemovedWhileRunning_FlashWritesAreAnsweredAsErrors) {
  TempDir dir;
  const std::string scene = dir.write("cell.yaml", "scanner: {}\n");
  const std::filesystem::path state = dir.path("state");
  std::filesystem::create_directory(state);
  const std::string flash = (state / "cell.flash").string();
  auto process = DaemonProcess::start(
      {"--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--flash", flash, "--timeout", "60"});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  auto host = TcpHost::connect(process->tcp_port());
  ASSERT_TRUE(host);
  const auto answer = [&](std::string_view request) {
    host->send(telegram(request));
    const auto payload = host->next_payload();
    return payload ? protocol::format_telegram(*payload) : std::string("(no reply)");
  };
  std::filesystem::remove_all(state);
  EXPECT_EQ(answer("SET_CONFIG 0010 0001 000c 0004"), "SET_CONFIG reply 0001");
  EXPECT_EQ(answer("SET_FILTER 0001 0001"), "SERVICE_FAILURE 0209 0006");
  EXPECT_EQ(answer("SET_FUNCTION 0000 0003 0800 0001"), "SET_FUNCTION reply ffff");
  EXPECT_EQ(answer("GET_CONFIG 0010"), "GET_CONFIG reply 0010 0001 000a 0004");  // unchanged
  EXPECT_EQ(answer("GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0870");
  EXPECT_NE(process->stderr_text().find("error: flash " + flash + " not saved: mkstemp: No such file or directory"),
            std::string::npos)
      << process->stderr_text();
  // The folder back: the same write is stored and answered as a success.
  std::filesystem::create_directory(state);
  EXPECT_EQ(answer("SET_FILTER 0001 0001"), "SET_FILTER reply 0001");
  std::ifstream image(flash);
  std::string first_line;
  std::getline(image, first_line);
  EXPECT_EQ(first_line, "ldoem-flash 1");
}

}  // namespace
}  // namespace ldoem::daemon::test
