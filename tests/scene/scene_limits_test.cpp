// Scene limits (issue 11): mesh validation, caps on objects and triangles, and YAML aliases
// that repeat a mesh import.
#include "ldoem/scene/scene_loader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>
#include "ldoem/test_support/temp_dir.hpp"
#include "scene_sources.hpp"

namespace ldoem::scene {
namespace {

using test::kScenes;

class SceneLimits : public ::testing::Test {
 protected:
  void write(const std::string& name, const std::string& text) { std::ofstream(folder_ / name) << text; }
  test_support::TempDir dir_;
  const std::filesystem::path folder_ = dir_.folder();
};

TEST_F(SceneLimits, FaceIndexingAMissingVertex_IsAMeshError) {
  write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
  auto result = load_scene_from_string("objects: [{mesh: {file: bad.obj}}]", (folder_ / "s.yaml").string());
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::mesh) << result.error().message();
  EXPECT_EQ(result.error().key_path, "objects[0].mesh.file");
}

TEST_F(SceneLimits, TooManyObjects_IsOutOfRange) {
  std::string yaml = "objects: [&o {sphere: {radius_m: 1}}";
  for (std::size_t i = 0; i < kMaxSceneObjects; ++i) yaml += ", *o";
  yaml += "]\n";
  auto result = load_scene_from_string(yaml, (folder_ / "s.yaml").string());
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::out_of_range);
  EXPECT_EQ(result.error().key_path, "objects");
}

TEST_F(SceneLimits, AliasesRepeatingABigMesh_HitTheTriangleCapAfterOneImport) {
  // large-rock.obj has 100800 triangles: 40 copies are more than kMaxSceneTriangles.
  static_assert(40 * 100800 > kMaxSceneTriangles);
  std::string yaml = "objects: [&rock {mesh: {file: meshes/large-rock.obj}}";
  for (int i = 1; i < 40; ++i) yaml += ", *rock";
  yaml += "]\n";
  auto result = load_scene_from_string(yaml, (kScenes / "limits.yaml").string());
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::out_of_range) << result.error().message();
  EXPECT_NE(result.error().message().find("triangles"), std::string::npos);
}

TEST_F(SceneLimits, ARepeatedMesh_BelowTheCapLoadsEveryCopy) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto result = load_scene_from_string("objects: [&t {mesh: {file: tri.obj}}, *t, *t]",
                                       (folder_ / "s.yaml").string());
  ASSERT_TRUE(result) << result.error().message();
  ASSERT_EQ(result->objects.size(), 3u);
  for (const auto& object : result->objects) EXPECT_EQ(std::get<Mesh>(object.shape).triangles.size(), 1u);
}

TEST_F(SceneLimits, HugeSceneFile_IsRefusedBeforeParsing) {
  const auto path = folder_ / "huge.yaml";
  {
    std::ofstream out(path);
    out << "description: x\n";
  }
  std::filesystem::resize_file(path, kMaxSceneFileBytes + 1);  // sparse: no disk used
  auto result = load_scene(path);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, SceneErrorKind::io);
}

}  // namespace
}  // namespace ldoem::scene
