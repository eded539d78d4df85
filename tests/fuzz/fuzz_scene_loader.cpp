// libFuzzer target: the scene loader (emulator/physics/scene) on arbitrary YAML text. It must
// return a Scene or a SceneError, never throw, crash or exhaust memory; an error always has a message.
// Mesh paths resolve against the working directory, where the fuzzer finds no mesh files.
//
// Issue 27: memory and time invariants. YAML aliases let a few bytes repeat big lists, and the
// node tree costs far more than its text, so the loader's limits (objects, waypoints in all,
// YAML nodes) must hold whatever the input: one input may raise the process's peak RSS by at
// most kMaxGrowthBytes and take at most kMaxCpuSeconds of this thread's CPU time (CPU, not wall
// time, so that a loaded machine does not fail the run).
#include <sys/resource.h>
#include <time.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "ldoem/scene/scene_loader.hpp"

namespace {

// kMaxSceneWaypoints waypoints of 64 bytes are 64 MiB; the rest of a scene from 8 KiB of text is
// far smaller. Twice that leaves room for the sanitizers' redzones.
constexpr long kMaxGrowthBytes = 128L << 20;
constexpr double kMaxCpuSeconds = 5.0;

long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss * 1024L;
}

double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const long peak_before = peak_rss_bytes();
  const double cpu_before = thread_cpu_seconds();
  const auto scene = ldoem::scene::load_scene_from_string(text, "fuzz.yaml");
  const long grown = peak_rss_bytes() - peak_before;
  const double cpu = thread_cpu_seconds() - cpu_before;
  if (grown > kMaxGrowthBytes || cpu > kMaxCpuSeconds) {
    std::fprintf(stderr, "scene loader: one input of %zu bytes raised the peak RSS by %ld MiB and took %.2f CPU s\n",
                 size, grown >> 20, cpu);
    std::abort();
  }
  if (!scene) {
    if (scene.error().message().empty()) std::abort();
    return 0;
  }
  if (scene->objects.size() > ldoem::scene::kMaxSceneObjects) std::abort();
  std::size_t waypoints = 0;
  for (const auto& object : scene->objects) {
    if (object.motion) {
      if (const auto* path = std::get_if<ldoem::scene::Waypoints>(&*object.motion)) waypoints += path->points.size();
    }
  }
  if (waypoints > ldoem::scene::kMaxSceneWaypoints) std::abort();
  return 0;
}
