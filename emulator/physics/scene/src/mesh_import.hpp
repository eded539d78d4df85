// Triangle meshes from OBJ/STL (and anything else assimp reads). Internal to ldoem_scene.
#pragma once

#include "ldoem/scene/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace ldoem::scene::detail {

// A mesh file larger than this is refused before assimp reads it.
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{256} << 20;

// Fills mesh.vertices_m (already multiplied by mesh.scale) and mesh.triangles from the file,
// after assimp's own validation (aiProcess_ValidateDataStructure) and a bounds check of every
// face index. A file with more than max_triangles triangles or max_vertices vertices is
// refused. Returns an error text, or nothing on success.
std::optional<std::string> import_mesh(const std::filesystem::path& file, Mesh& mesh, std::size_t max_triangles,
                                       std::size_t max_vertices);

}  // namespace ldoem::scene::detail
