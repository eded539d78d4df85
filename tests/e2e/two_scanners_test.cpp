// Issue 15: the corridor e2e and ldoem-hub against one ldoem-emud holding two scanners
// (scenes/corridor-two-scanners.yaml). "paper" stands where corridor.yaml's scanner stands with
// its seed and effects, so its cloud must be the corridor's, point for point, except for the
// beams that meet the housing of "side"; "side" looks back at "paper" and must see its housing.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "corridor_expectations.hpp"
#include "corridor_scan.hpp"
#include "ldoem/cloud/cloud_file.hpp"

namespace ldoem::e2e {
namespace {

using namespace std::chrono_literals;

// scenes/corridor-two-scanners.yaml: side's pivot in paper's pivot frame (both 0.5 m high), and
// the housing both scanners have (HousingConfig's defaults).
constexpr double kSideX = 1.8;
constexpr double kSideY = 0.25;
constexpr double kPaperToSide = 1.81728;  // hypot(1.8, 0.25): side's head angle 0 points at paper
constexpr double kHousingRadius = 0.06;
constexpr double kHousingHalfHeight = 0.08;
// A point on a housing: within quantisation (1/256 m), noise (sigma 1.5 mm, 4 sigma) and float.
constexpr double kOnSurface = 1.0 / 256.0 + 0.006 + 1e-4;

// Every occurrence (the scene's comments name the same ports and paths).
void replace_all(std::string& text, const std::string& from, const std::string& to) {
  std::size_t replaced = 0;
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
    ++replaced;
  }
  EXPECT_GT(replaced, 0u) << from;
}

// The shipped scene with the test's own ports (any free one) and LPT ptys.
std::string shipped_scene_in(const TempDir& dir, const std::string& name) {
  std::string text = read_file(std::string(LDOEM_SOURCE_DIR) + "/scenes/corridor-two-scanners.yaml");
  replace_all(text, "127.0.0.1:49152", "127.0.0.1:0");
  replace_all(text, "127.0.0.1:49153", "127.0.0.1:0");
  replace_all(text, "/tmp/ldoem-paper-lpt", lpt_path(dir, name));
  replace_all(text, "/tmp/ldoem-side-lpt", dir.path(name + "-side-lpt"));
  return dir.write(name + ".yaml", text);
}

// Does the ray from the pivot through `p` meet a vertical cylinder (axis at cx, cy; |z| <=
// half_height) of `radius`? Slab test: the part of the ray inside the infinite cylinder overlaps
// the part between the two cap planes.
bool ray_meets_cylinder(const cloud::Point3f& p, double cx, double cy, double radius, double half_height) {
  const double length = std::sqrt(double(p.x_m) * p.x_m + double(p.y_m) * p.y_m + double(p.z_m) * p.z_m);
  const double dx = p.x_m / length, dy = p.y_m / length, dz = p.z_m / length;
  const double a = dx * dx + dy * dy;
  const double b = -2.0 * (dx * cx + dy * cy);
  const double c = cx * cx + cy * cy - radius * radius;
  const double discriminant = b * b - 4 * a * c;
  if (a == 0.0 || discriminant < 0.0) return false;
  const double t0 = (-b - std::sqrt(discriminant)) / (2 * a);
  const double t1 = (-b + std::sqrt(discriminant)) / (2 * a);
  double z0 = -1e9, z1 = 1e9;
  if (dz != 0.0) {
    z0 = std::min(-half_height / dz, half_height / dz);
    z1 = std::max(-half_height / dz, half_height / dz);
  }
  return std::max(t0, z0) <= std::min(t1, z1) && std::min(t1, z1) > 0.0;
}

bool on_housing(const cloud::Point3f& p, double cx, double cy) {
  const double from_axis = std::hypot(p.x_m - cx, p.y_m - cy);
  return std::abs(from_axis - kHousingRadius) <= kOnSurface ||
         (from_axis <= kHousingRadius + kOnSurface && std::abs(std::abs(p.z_m) - kHousingHalfHeight) <= kOnSurface);
}

// What is asserted: the two-scanner scan of "paper" still fits the paper's cylinder and wall and
// has all 9801 points; every beam whose ray clearly meets side's housing (1 mm inside its edge)
// ends on that housing, nearer than in the corridor's cloud; every beam that clearly misses it
// (1 mm outside) gives the corridor's point bit for bit; and there are such occluded beams.
TEST(TwoScanners, CorridorCloudOfOneScanner_IsTheCorridorsExceptWhereTheOtherHousingStands) {
  TempDir dir;
  const ScanRun corridor = scan_corridor(dir, "corridor", Route::tcp);
  ScanSettings two;
  two.scanners_scene = shipped_scene_in(dir, "two");
  const ScanRun paper = scan_corridor(dir, "two", Route::tcp, two);
  ASSERT_EQ(corridor.exit_status, 0) << corridor.failure;
  expect_paper_scan(paper);

  const auto alone = cloud::read_cloud_file(corridor.ply_path);
  const auto beside = cloud::read_cloud_file(paper.ply_path);
  ASSERT_TRUE(alone.has_value() && beside.has_value());
  ASSERT_EQ(alone->size(), beside->size());
  std::size_t occluded = 0, unchanged = 0;
  for (std::size_t i = 0; i < alone->size(); ++i) {
    const cloud::Point3f& before = alone->positions()[i];
    const cloud::Point3f& now = beside->positions()[i];
    if (ray_meets_cylinder(before, kSideX, kSideY, kHousingRadius - 0.001, kHousingHalfHeight - 0.001)) {
      ++occluded;
      EXPECT_TRUE(on_housing(now, kSideX, kSideY)) << "point " << i << " " << now.x_m << " " << now.y_m << " " << now.z_m;
      EXPECT_LT(std::hypot(now.x_m, now.y_m), std::hypot(before.x_m, before.y_m)) << "point " << i;
    } else if (!ray_meets_cylinder(before, kSideX, kSideY, kHousingRadius + 0.001, kHousingHalfHeight + 0.001)) {
      ++unchanged;
      EXPECT_EQ(now, before) << "point " << i;
    }
  }
  std::printf("two scanners: %zu of %zu paper beams on side's housing, %zu clearly unchanged\n", occluded,
              alone->size(), unchanged);
  EXPECT_GT(occluded, 100u);  // about 15 beams x 28 layers
  EXPECT_GT(unchanged, alone->size() - 2 * occluded);
}

// ldoem-hub with two devices, both in one daemon: each is scanned through the hub. paper's cloud
// is the direct scan's byte for byte; side's cloud shows paper's housing where paper stands.
TEST(TwoScanners, HubWithTwoDevicesOfOneDaemon_ScansEachAndSideSeesPapersHousing) {
  TempDir dir;
  ScanSettings direct_settings;
  direct_settings.scanners_scene = shipped_scene_in(dir, "direct");
  const ScanRun direct = scan_corridor(dir, "direct", Route::tcp, direct_settings);
  ASSERT_EQ(direct.exit_status, 0) << direct.failure;

  const std::string scene = shipped_scene_in(dir, "hub");
  auto daemon = ChildProcess::start(LDOEM_EMUD_PATH, {"--scene", scene, "--no-can", "--no-flash", "--virtual-time",
                                                      "--timeout", "900"},
                                    dir.path("hub-daemon"));
  ASSERT_TRUE(daemon && daemon->wait_for_line("ready", false, 60s)) << (daemon ? daemon->stderr_text() : "");
  std::map<std::string, std::string> addresses;  // "scanner NAME" then its "tcp ADDRESS"
  {
    std::istringstream lines(daemon->stdout_text());
    std::string current;
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("scanner ", 0) == 0) current = line.substr(8);
      if (line.rfind("tcp ", 0) == 0) addresses[current] = line.substr(4);
    }
  }
  ASSERT_EQ(addresses.size(), 2u) << daemon->stdout_text();
  const std::string config = dir.write("hub.yaml", "devices:\n"
                                                   "  - name: paper\n"
                                                   "    scanner: tcp:" + addresses["paper"] + "\n"
                                                   "    lpt: lpt:pty:" + lpt_path(dir, "hub") + "\n"
                                                   "  - name: side\n"
                                                   "    scanner: tcp:" + addresses["side"] + "\n"
                                                   "    lpt: lpt:pty:" + dir.path("hub-side-lpt") + "\n");
  auto hub = ChildProcess::start(LDOEM_HUB_PATH, {"--config", config, "--listen", "127.0.0.1:0"}, dir.path("hub"));
  ASSERT_TRUE(hub && hub->wait_for_line("listening on", true, 60s)) << (hub ? hub->stderr_text() : "");
  ASSERT_FALSE(hub_port(*hub).empty()) << hub->stderr_text();
  const std::string hub_address = "127.0.0.1:" + hub_port(*hub);

  const auto scan_through_hub = [&](const std::string& device) {
    const std::string ply = dir.path("hub-" + device + ".ply");
    auto scan = ChildProcess::start(LDOEM_SCAN_PATH,
                                    {"--hub", hub_address, "--hub-device", device, "--horizontal-apex", "20",
                                     "--horizontal-resolution", "0.25", "--vertical-apex", "21.6",
                                     "--vertical-resolution", "0.18", "--speed", "10", "--out", ply},
                                    dir.path("hub-scan-" + device));
    EXPECT_TRUE(scan.has_value());
    if (!scan) return std::string();
    const auto status = scan->wait(300s);
    EXPECT_EQ(status, std::optional<int>(0)) << scan->stderr_text();
    return ply;
  };
  const std::string paper_ply = scan_through_hub("paper");
  EXPECT_EQ(read_file(paper_ply), direct.ply_bytes);

  const auto side = cloud::read_cloud_file(scan_through_hub("side"));
  ASSERT_TRUE(side.has_value());
  // In side's pivot frame paper's pivot is kPaperToSide straight ahead.
  std::size_t on_paper = 0;
  for (const cloud::Point3f& p : side->positions()) {
    if (!std::isfinite(p.x_m)) continue;
    const double from_paper = std::hypot(p.x_m - kPaperToSide, p.y_m);
    if (from_paper > 0.3) continue;  // nothing else stands within 0.3 m of paper's pivot
    ++on_paper;
    EXPECT_TRUE(on_housing(p, kPaperToSide, 0.0)) << p.x_m << " " << p.y_m << " " << p.z_m;
  }
  std::printf("two scanners: %zu of side's points on paper's housing\n", on_paper);
  EXPECT_GT(on_paper, 100u);
}

}  // namespace
}  // namespace ldoem::e2e
