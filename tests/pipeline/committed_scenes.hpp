// The committed scenes the pipeline tests run: the two plain ones and every hard one.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace ldoem::sensor::test {

inline const std::filesystem::path kScenes = std::filesystem::path(LDOEM_SOURCE_DIR) / "scenes";

// Paths relative to kScenes.
inline const std::vector<std::string> kSceneFiles{
    "corridor.yaml",           "minimal.yaml",           "hard/box_edges.yaml",
    "hard/far_from_origin.yaml", "hard/grazing_plane.yaml", "hard/mesh_edges.yaml",
    "hard/scanner_inside_box.yaml", "hard/tiny_and_huge.yaml",
};

}  // namespace ldoem::sensor::test
