// libFuzzer target: the scene loader (emulator/scene) on arbitrary YAML text. It must return a
// Scene or a SceneError, never throw, crash or exhaust memory; an error always has a message.
// Mesh paths resolve against the working directory, where the fuzzer finds no mesh files.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ldoem/scene/scene_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto scene = ldoem::scene::load_scene_from_string(text, "fuzz.yaml");
  if (!scene) {
    if (scene.error().message().empty()) std::abort();
    return 0;
  }
  if (scene->objects.size() > ldoem::scene::kMaxSceneObjects) std::abort();
  return 0;
}
