#include "mesh_import.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <system_error>

namespace ldoem::scene::detail {

std::optional<std::string> import_mesh(const std::filesystem::path& file, Mesh& mesh) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return "mesh file not found: " + file.string();

  Assimp::Importer importer;
  // Drop points and lines (we cast rays at surfaces), bake node transforms into one frame.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* imported = importer.ReadFile(
      file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (imported == nullptr) {
    return "cannot read mesh " + file.string() + ": " + importer.GetErrorString();
  }

  mesh.vertices_m.clear();
  mesh.triangles.clear();
  const Eigen::Vector3f scale = mesh.scale.cast<float>();
  for (unsigned m = 0; m < imported->mNumMeshes; ++m) {
    const aiMesh* part = imported->mMeshes[m];
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
      mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  if (mesh.triangles.empty()) return "mesh " + file.string() + " has no triangles";
  return std::nullopt;
}

}  // namespace ldoem::scene::detail
