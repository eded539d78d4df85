// ldoem_bench_daemon_scaling <scene.yaml> <paper|all> <scanners>: scanners per core in real time,
// measured on one ldoem-emud thread (issue 15). The scene gets a `scanners:` list of that many
// LD-OEMs (the first at the scene's pivot, the others on a 0.5 m grid behind it, x in [-10, 0] m,
// y in [-5, 5] m, all facing +x: open floor in corridor.yaml and large.yaml) and one Daemon holds
// them all, one device instance each, on one scene world with their housings. Each device has a
// memory endpoint whose host streams (GET_PROFILE 0) at the most the device sustains: 20 Hz at
// 0.5 deg, measuring 270 of the 360 deg (D4's sector table), 10 800 beams/s per scanner. 14 400
// beams/s (the whole turn) is the device's peak pulse rate, not a rate it may keep up: the
// control unit refuses a configuration whose mean exceeds 10 800 Hz (TRANS_MEASURE return code
// 2, spec 5, control/sector_table.hpp); the probe below shows it on a running daemon.
//
// After every device has sent its first profile, the daemon's loop runs 2 simulated seconds in
// virtual time on this thread; the host side (taking the profiles off the memory endpoints) runs
// between loop rounds on the same thread and is counted too. Printed as one JSON line:
//   cpu_s_per_simulated_s   thread CPU time per simulated second, all scanners together
//   scanners_per_core       scanners / cpu_s_per_simulated_s
//   profiles                profiles received in the window (must be scanners x 20 x 2)
//   rss_mib, heap_mib       resident set and heap bytes in use after start-up and the window,
//                           minus the same before the daemon existed (scene loaded)
//   rss_total_mib, heap_total_mib   the same for the whole process, nothing subtracted
// Memory per added scanner is the difference of two runs (1 and N scanners) in the script.
//
// ldoem_bench_daemon_scaling <scene.yaml> probe-full-turn <hz> <step ticks>: one scanner whose
// flash measures the whole turn (one normal-measurement sector, stop 5760) at that motor speed
// and angle step; prints TRANS_MEASURE's return code as one JSON line (0 = it measures).
#include "support/bench_scenes.hpp"
#include "support/process_meters.hpp"

#include <ldoem/daemon/daemon.hpp>
#include <ldoem/endpoints/memory_endpoint.hpp>
#include <ldoem/protocol/messages.hpp>
#include <ldoem/protocol/text.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace {

using ldoem::bench::current_rss_mib;
using ldoem::bench::heap_in_use_mib;
using ldoem::bench::thread_cpu_s;

using namespace ldoem;
using namespace std::chrono_literals;

constexpr double kSimulatedSeconds = 2.0;
constexpr double kRevolutionHz = 20.0;
constexpr double kBeamsPerRevolution = 540.0;  // 270 deg at 0.5 deg
constexpr double kGridStep_m = 0.5;
constexpr int kGridSide = 21;  // 21 x 21 places: up to 441 scanners

// The scene's scanner, `count` times: 20 Hz, 0.5 deg, D4's sectors (270 deg measured), each on
// its own grid place and CAN identifier pair (no CAN here; the loader's rule is kept).
scene::Scene with_scanners(scene::Scene scene, int count) {
  for (int k = 0; k < count; ++k) {
    scene::ScannerEntry entry;
    entry.name = "s" + std::to_string(k);
    entry.config = scene.scanner;
    entry.effects = scene.effects;
    const int column = k % kGridSide;
    const int row = k / kGridSide;
    entry.config.pivot_pose.position_m.x() -= kGridStep_m * column;
    entry.config.pivot_pose.position_m.y() += kGridStep_m * (row % 2 == 0 ? row / 2 : -(row + 1) / 2);
    entry.config.flash.motor_speed_hz = 20;
    entry.config.flash.angle_step_ticks = 8;
    entry.config.flash.sectors = scene::FlashDefaults{}.sectors;
    entry.config.flash.can_request_id = static_cast<std::uint16_t>(0x100 + 2 * k);
    entry.config.flash.can_response_id = static_cast<std::uint16_t>(0x101 + 2 * k);
    scene.scanners.push_back(std::move(entry));
  }
  scene.scanner = scene.scanners.front().config;
  return scene;
}

[[noreturn]] void fail(const std::string& why) {
  std::fprintf(stderr, "ldoem_bench_daemon_scaling: %s\n", why.c_str());
  std::exit(1);
}

struct Started {
  std::unique_ptr<daemon::Daemon> daemon;
  std::vector<endpoints::MemoryEndpoint*> hosts;  // one per scanner, owned by the daemon
};

// One daemon in virtual time with no CAN and flash in memory, a memory endpoint per scanner.
Started start_daemon(const std::string& scene_path, scene::Scene scene, std::ostream& out, std::ostream& log) {
  daemon::Options options;
  options.scene_path = scene_path;
  options.can_interface.reset();
  options.flash_mode = daemon::FlashMode::memory;
  options.virtual_time = true;
  Started started;
  auto created = daemon::Daemon::create_with_endpoints(options, std::move(scene), out, log, [&](std::size_t) {
    auto memory = std::make_unique<endpoints::MemoryEndpoint>();
    started.hosts.push_back(memory.get());
    std::vector<std::unique_ptr<endpoints::HostEndpoint>> extra;
    extra.push_back(std::move(memory));
    return extra;
  });
  if (!created) fail(created.error().message);
  started.daemon = std::move(*created);
  return started;
}

// Every host sends `request`; returns each one's first answer once all have one.
std::vector<protocol::Bytes> ask_all(Started& started, const char* request) {
  auto& hosts = started.hosts;
  for (auto* host : hosts) host->host_sends(0, protocol::parse_telegram(request).value());
  std::vector<protocol::Bytes> answers(hosts.size());
  std::vector<bool> answered(hosts.size(), false);
  std::size_t count = 0;
  const bool all_answered = started.daemon->run_until(
      [&] {
        for (std::size_t i = 0; i < hosts.size(); ++i) {
          for (auto& sent : hosts[i]->take_sent()) {
            if (answered[i]) continue;
            answered[i] = true;
            answers[i] = std::move(sent.payload);
            ++count;
          }
        }
        return count == hosts.size();
      },
      600s);
  if (!all_answered) fail(std::string(request) + " not answered by every scanner");
  return answers;
}

// TRANS_MEASURE's return code for a flash that measures the whole turn at `hz` and `step_ticks`.
int probe_full_turn(const std::string& scene_path, scene::Scene scene, int hz, int step_ticks) {
  scene = with_scanners(std::move(scene), 1);
  scene::ScannerConfig& config = scene.scanners.front().config;
  config.flash.motor_speed_hz = static_cast<std::uint16_t>(hz);
  config.flash.angle_step_ticks = static_cast<std::uint16_t>(step_ticks);
  config.flash.sectors = {};
  config.flash.sectors[0] = scene::SectorDefault{3, 5760};  // normal measurement, 0..360 deg
  scene.scanner = config;
  std::ostringstream out;
  std::ostringstream log;
  Started started = start_daemon(scene_path, std::move(scene), out, log);
  ask_all(started, "TRANS_ROTATE 0000");
  const protocol::Bytes answer = ask_all(started, "TRANS_MEASURE").front();
  const auto decoded = protocol::decode_response(answer);
  const auto* reply = decoded ? std::get_if<protocol::TransMeasureReply>(&*decoded) : nullptr;
  if (reply == nullptr) fail("TRANS_MEASURE answered " + protocol::format_telegram(answer));
  std::printf("{\"probe\": \"full-turn\", \"motor_hz\": %d, \"angle_step_ticks\": %d, \"beams_per_s\": %d, "
              "\"trans_measure_return_code\": %u}\n",
              hz, step_ticks, hz * 5760 / step_ticks, static_cast<unsigned>(reply->return_code));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = std::string("usage: ") + argv[0] +
                            " scenes/<name>.yaml paper|all <scanners 1..441>\n"
                            "       " + argv[0] + " scenes/<name>.yaml probe-full-turn <5..20 Hz> <step ticks 1..5760>";
  if (argc == 5 && std::string(argv[2]) == "probe-full-turn") {
    const int hz = std::atoi(argv[3]);
    const int step_ticks = std::atoi(argv[4]);
    if (hz < 5 || hz > 20 || step_ticks < 1 || step_ticks > 5760 || 5760 % step_ticks != 0) fail(usage);
    return probe_full_turn(argv[1], bench::load_repository_scene(argv[1]), hz, step_ticks);
  }
  if (argc != 4) fail(usage);
  const std::string effects_name = argv[2];
  const int scanners = std::atoi(argv[3]);
  if ((effects_name != "paper" && effects_name != "all") || scanners < 1 || scanners > kGridSide * kGridSide) fail(usage);
  using scene::Effect;
  // "all": every effect a scene can name together (snr_noise replaces noise, so it is left out;
  // bus_timing only shapes CAN, which this run does not use).
  const std::vector<Effect> effects =
      effects_name == "paper"
          ? std::vector<Effect>{Effect::noise, Effect::intensity, Effect::incidence}
          : std::vector<Effect>{Effect::noise,         Effect::intensity,     Effect::incidence,
                                Effect::mixed_pixels,  Effect::motor_dynamics, Effect::head_dynamics,
                                Effect::sweep_motion,  Effect::bus_timing,     Effect::waveform,
                                Effect::atmosphere};
  scene::Scene scene = with_scanners(bench::with_effects(bench::load_repository_scene(argv[1]), effects), scanners);
  const double rss_before_mib = current_rss_mib();
  const double heap_before_mib = heap_in_use_mib();

  std::ostringstream out;
  std::ostringstream log;
  Started running = start_daemon(argv[1], std::move(scene), out, log);
  daemon::Daemon& daemon = *running.daemon;
  const auto& hosts = running.hosts;

  // Every host: spin up at the flash's 20 Hz, measure, then stream profiles (format 0x39ff),
  // each request once the previous one is answered (TRANS_MEASURE answers once at speed).
  ask_all(running, "TRANS_ROTATE 0000");
  for (const auto& answer : ask_all(running, "TRANS_MEASURE")) {
    const auto decoded = protocol::decode_response(answer);
    const auto* reply = decoded ? std::get_if<protocol::TransMeasureReply>(&*decoded) : nullptr;
    if (reply == nullptr || reply->return_code != protocol::measure_return::kOk) {
      fail("TRANS_MEASURE refused: " + protocol::format_telegram(answer));
    }
  }
  for (auto* host : hosts) host->host_sends(0, protocol::parse_telegram("GET_PROFILE 0000 39ff").value());
  std::vector<bool> streaming(hosts.size(), false);
  std::size_t started = 0;
  std::uint64_t profiles = 0;
  const auto take_all = [&] {
    for (std::size_t i = 0; i < hosts.size(); ++i) {
      for (const auto& sent : hosts[i]->take_sent()) {
        if (sent.payload.size() < 2 || sent.payload[0] != 0x83 || sent.payload[1] != 0x01) continue;  // a profile
        ++profiles;
        if (!streaming[i]) {
          streaming[i] = true;
          ++started;
        }
      }
    }
  };
  if (!daemon.run_until([&] { take_all(); return started == hosts.size(); }, 600s)) fail("not every scanner streams");
  profiles = 0;
  const base::SimTime window_start = daemon.now();
  const auto window_end = window_start + std::chrono::duration_cast<base::SimTime>(
                                             std::chrono::duration<double>(kSimulatedSeconds));
  const double cpu_start_s = thread_cpu_s();
  if (!daemon.run_until([&] { take_all(); return daemon.now() >= window_end; }, 900s)) fail("window not reached");
  const double cpu_s = thread_cpu_s() - cpu_start_s;
  const double simulated_s = std::chrono::duration<double>(daemon.now() - window_start).count();
  const double cpu_per_simulated_s = cpu_s / simulated_s;
  const auto counters = daemon.counters();
  std::printf("{\"scene\": \"%s\", \"effects\": \"%s\", \"scanners\": %d, \"beams_per_s_each\": %.0f, "
              "\"simulated_s\": %.3f, \"profiles\": %llu, \"skipped_profiles\": %llu, "
              "\"cpu_s_per_simulated_s\": %.6f, \"scanners_per_core\": %.1f, \"rss_mib\": %.2f, \"heap_mib\": %.3f, "
              "\"rss_total_mib\": %.2f, \"heap_total_mib\": %.3f}\n",
              argv[1], effects_name.c_str(), scanners, kRevolutionHz * kBeamsPerRevolution, simulated_s,
              static_cast<unsigned long long>(profiles), static_cast<unsigned long long>(counters.skipped_profiles),
              cpu_per_simulated_s, static_cast<double>(scanners) / cpu_per_simulated_s,
              current_rss_mib() - rss_before_mib, heap_in_use_mib() - heap_before_mib, current_rss_mib(), heap_in_use_mib());
  return 0;
}
