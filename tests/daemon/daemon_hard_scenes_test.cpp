// Every scenes/hard/ file through ldoem-emud with every effect on (D9 and D13; snr_noise stands
// for noise, which the loader refuses beside it): the daemon starts, streams profiles over TCP,
// and every point is either "no echo" (0, 0) or a range inside the scene's limits with an ECHO.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

const std::filesystem::path kHardScenes = std::filesystem::path(LDOEM_SOURCE_DIR) / "scenes" / "hard";

constexpr const char* kEveryEffect =
    "effects: [snr_noise, intensity, incidence, mixed_pixels, waveform, atmosphere, motor_dynamics, "
    "head_dynamics, sweep_motion, bus_timing]\n";

// The scene's text with every effect named and its mesh paths made absolute (the copy lives in a
// temporary folder).
std::string with_every_effect(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string relative = "file: ../meshes/";
  const std::string absolute = "file: " + (kHardScenes.parent_path() / "meshes").string() + "/";
  for (std::size_t at = yaml.find(relative); at != std::string::npos; at = yaml.find(relative, at)) {
    yaml.replace(at, relative.size(), absolute);
    at += absolute.size();
  }
  return yaml + "\n" + kEveryEffect;
}

class HardSceneInDaemon : public ::testing::TestWithParam<std::string> {};

TEST_P(HardSceneInDaemon, EveryEffectOn_ProfilesStayInsideTheLimits) {
  TempDir dir;
  const std::string scene_path = dir.write("scene.yaml", with_every_effect(kHardScenes / GetParam()));
  const auto scene = scene::load_scene(scene_path);
  ASSERT_TRUE(scene.has_value()) << scene.error().message();
  auto daemon = DaemonProcess::start({"--scene", scene_path, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--virtual-time",
                                      "--no-flash", "--timeout", "120"});
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "no process");
  auto host = TcpHost::connect(daemon->tcp_port());
  ASSERT_TRUE(host);
  for (const char* request : {"TRANS_ROTATE 0000", "TRANS_MEASURE"}) {
    host->send(telegram(request));
    ASSERT_TRUE(host->next_payload(30s)) << request << ": " << daemon->stderr_text();
  }
  host->send(telegram("GET_PROFILE 0003 3dff"));
  const double min_q8 = scene->scanner.min_range_m * 256.0;
  const double max_q8 = scene->scanner.max_range_m * 256.0;
  std::size_t points = 0;
  for (int i = 0; i < 3; ++i) {
    const auto payload = host->next_payload(30s);
    ASSERT_TRUE(payload) << "profile " << i << ": " << daemon->stderr_text();
    const auto profile = protocol::decode_profile(*payload);
    ASSERT_TRUE(profile.has_value()) << "profile " << i;
    for (const protocol::SectorBlock& sector : profile->sectors) {
      for (const protocol::ProfilePoint& point : sector.points) {
        ++points;
        if (point.distance_q8_m == 0) {
          EXPECT_EQ(point.echo, 0);
          continue;
        }
        EXPECT_GE(point.distance_q8_m, std::floor(min_q8));
        EXPECT_LE(point.distance_q8_m, std::ceil(max_q8));
        EXPECT_GT(point.echo, 0);
      }
    }
  }
  EXPECT_GT(points, 0u);
  EXPECT_TRUE(daemon->alive());
}

INSTANTIATE_TEST_SUITE_P(HardScenes, HardSceneInDaemon,
                         ::testing::Values("box_edges.yaml", "far_from_origin.yaml", "grazing_plane.yaml",
                                           "mesh_edges.yaml", "scanner_inside_box.yaml", "tiny_and_huge.yaml"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(0, info.param.find('.'));
                           return name;
                         });

}  // namespace
}  // namespace ldoem::daemon::test
