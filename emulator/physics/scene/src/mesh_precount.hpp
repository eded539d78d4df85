// Issue 27 (D8): a mesh's size read from its header or counted in one streaming pass, before
// assimp imports it. A binary STL header that claimed 5 000 000 triangles, followed by 250 MB of
// zeros, took 1.66 GB and 10 s inside assimp before the triangle limit was applied. Internal to
// ldoem_scene.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace ldoem::scene::detail {

// Formats without a header count or a cheap pre-count (assimp reads dozens) are bounded by their
// file size alone, at this tighter cap.
inline constexpr std::uintmax_t kMaxUncountedMeshFileBytes = std::uintmax_t{32} << 20;

struct MeshCount {
  std::size_t triangles = 0;  // an upper bound of what the import can give (before dropping)
  std::size_t vertices = 0;
};

// Counts what the file at `fd` (a regular file of `bytes` bytes, read from offset 0) can hold:
// binary STL from its header (which must agree with the file size), ASCII STL facets, OBJ faces
// (a polygon of n corners is n - 2 triangles) and vertices, PLY header elements. Returns nothing
// for other formats. `extension` is lower case with its dot (".obj"). An error text when the
// header contradicts the file.
struct MeshCountResult {
  std::optional<MeshCount> count;
  std::optional<std::string> problem;
};
MeshCountResult precount_mesh(int fd, std::uintmax_t bytes, const std::string& extension);

}  // namespace ldoem::scene::detail
