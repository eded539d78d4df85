// Where the scene tests' scenes come from: the committed scenes folder, and YAML text that must
// load.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string_view>

#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::scene::test {

inline const std::filesystem::path kScenes = std::filesystem::path(LDOEM_SOURCE_DIR) / "scenes";

// The scene `yaml` describes; a load error fails the calling test (and gives the default scene).
inline Scene load_ok(std::string_view yaml, std::string_view name = "test.yaml") {
  auto result = load_scene_from_string(yaml, name);
  EXPECT_TRUE(result.has_value()) << (result ? "" : result.error().message());
  return result ? std::move(result).value() : Scene{};
}

}  // namespace ldoem::scene::test
