#include "mesh_import.hpp"

#include "mesh_precount.hpp"

#include "ldoem/base/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>

namespace ldoem::scene::detail {

std::optional<std::string> import_mesh(const std::filesystem::path& file, Mesh& mesh, std::size_t max_triangles,
                                       std::size_t max_vertices) {
  // Issue 27: a FIFO, a device or a folder is named as such (it was "not found"), and the size
  // comes from fstat of what was opened.
  auto opened = base::open_regular_file(file, O_RDONLY);
  if (!opened) {
    if (opened.error().error_number == ENOENT) return "mesh file not found: " + file.string();
    return "mesh " + file.string() + ": " + opened.error().text;
  }
  struct stat info {};
  if (::fstat(opened->get(), &info) != 0) return "mesh " + file.string() + ": fstat failed";
  const auto bytes = static_cast<std::uintmax_t>(info.st_size);
  if (bytes > kMaxMeshFileBytes) {
    return "mesh " + file.string() + " is larger than " + std::to_string(kMaxMeshFileBytes >> 20) + " MiB";
  }
  // D8: the triangles and vertices are counted from the header or in one streaming pass before
  // assimp spends memory on them; formats without a count have a tighter size cap instead.
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const MeshCountResult counted = precount_mesh(opened->get(), bytes, extension);
  if (counted.problem) return "mesh " + file.string() + ": " + *counted.problem;
  if (counted.count && (counted.count->triangles > max_triangles || counted.count->vertices > max_vertices)) {
    return "mesh " + file.string() + " has " + std::to_string(counted.count->triangles) + " triangles and " +
           std::to_string(counted.count->vertices) + " vertices, more than the scene's remaining budget of " +
           std::to_string(max_triangles) + " triangles or " + std::to_string(max_vertices) + " vertices";
  }
  if (!counted.count && bytes > kMaxUncountedMeshFileBytes) {
    return "mesh " + file.string() + " is larger than " + std::to_string(kMaxUncountedMeshFileBytes >> 20) +
           " MiB (the cap for formats other than OBJ, STL and PLY, whose triangles are counted before import)";
  }
  opened->reset();

  Assimp::Importer importer;
  // Drop points and lines (we cast rays at surfaces), bake node transforms into one frame.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* imported = importer.ReadFile(
      file.string(), aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (imported == nullptr) {
    return "cannot read mesh " + file.string() + ": " + importer.GetErrorString();
  }

  mesh.vertices_m.clear();
  mesh.triangles.clear();
  const Eigen::Vector3f scale = mesh.scale.cast<float>();
  for (unsigned m = 0; m < imported->mNumMeshes; ++m) {
    const aiMesh* part = imported->mMeshes[m];
    if (part == nullptr || (part->mNumVertices > 0 && part->mVertices == nullptr) ||
        (part->mNumFaces > 0 && part->mFaces == nullptr)) {
      return "mesh " + file.string() + " has a part without vertex or face data";
    }
    if (mesh.vertices_m.size() + part->mNumVertices > max_vertices ||
        mesh.triangles.size() + part->mNumFaces > max_triangles) {
      return "mesh " + file.string() + " has more than the scene's remaining budget of " +
             std::to_string(max_triangles) + " triangles or " + std::to_string(max_vertices) + " vertices";
    }
    const auto base = static_cast<std::uint32_t>(mesh.vertices_m.size());
    for (unsigned v = 0; v < part->mNumVertices; ++v) {
      const aiVector3D& p = part->mVertices[v];
      const Eigen::Vector3f vertex(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
      if (!vertex.allFinite()) return "mesh " + file.string() + " has a non-finite vertex";
      mesh.vertices_m.push_back(vertex);
    }
    for (unsigned f = 0; f < part->mNumFaces; ++f) {
      const aiFace& face = part->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines, if any survived
      if (face.mIndices == nullptr || face.mIndices[0] >= part->mNumVertices ||
          face.mIndices[1] >= part->mNumVertices || face.mIndices[2] >= part->mNumVertices) {
        return "mesh " + file.string() + ": face " + std::to_string(f) + " indexes a vertex that does not exist";
      }
      mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  if (mesh.triangles.empty()) return "mesh " + file.string() + " has no triangles";
  return std::nullopt;
}

}  // namespace ldoem::scene::detail
