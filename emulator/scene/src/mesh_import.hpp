// Triangle meshes from OBJ/STL (and anything else assimp reads). Internal to ldoem_scene.
#pragma once

#include "ldoem/scene/scene.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace ldoem::scene::detail {

// Fills mesh.vertices_m (already multiplied by mesh.scale) and mesh.triangles from the file.
// Returns an error text, or nothing on success.
std::optional<std::string> import_mesh(const std::filesystem::path& file, Mesh& mesh);

}  // namespace ldoem::scene::detail
