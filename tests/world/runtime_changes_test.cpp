// D12 runtime changes on world::SceneCaster (the control socket's add-object, remove-object and
// move-object): each holds from its device time on, exactly; static ones through static epochs
// that are dropped once no ray can reach them; a removed body stops colliding.
#include "world_test_support.hpp"

#include <thread>

namespace ldoem::world {
namespace {

using testing::ray_at;
using testing::scene_from;

const Eigen::Vector3d kAhead = Eigen::Vector3d::UnitX();

std::optional<double> range_at(const SceneCaster& caster, double t_s) {
  const auto hit = caster.cast(ray_at(Eigen::Vector3d(0, 0, 0.5), kAhead, t_s));
  return hit ? std::optional<double>(hit->range_m) : std::nullopt;
}

scene::SceneObject box(const std::string& name, double x) {
  scene::SceneObject object;
  object.name = name;
  object.shape = scene::Box{Eigen::Vector3d(0.5, 2, 2)};
  object.pose.position_m = Eigen::Vector3d(x, 0, 0.5);
  return object;
}

TEST(RuntimeChanges, StaticAddRemoveAndMoveHoldFromTheirTimeAndEpochsAreDropped) {
  SceneCaster caster(scene_from("objects:\n  - name: wall\n    box: {size_m: [0.5, 10, 5]}\n    pose: {position_m: [10.25, 0, 0]}\n"));
  caster.prepare(0.0, 0.1);
  ASSERT_EQ(caster.add_object(box("crate", 4.25), 1.0).value(), 1.0);
  scene::Pose nearer;
  nearer.position_m = Eigen::Vector3d(7.25, 0, 0);
  ASSERT_EQ(caster.move_object("wall", nearer, 1.5, false).value(), 1.5);
  ASSERT_EQ(caster.remove_object("crate", 2.0).value(), 2.0);
  EXPECT_EQ(caster.static_epochs(), 2u) << "the added crate went to the moving index; the wall's move is an epoch";
  EXPECT_NEAR(*range_at(caster, 0.999), 10.0, 1e-9);
  EXPECT_NEAR(*range_at(caster, 1.0), 4.0, 1e-9);
  EXPECT_NEAR(*range_at(caster, 1.9), 4.0, 1e-9);
  EXPECT_NEAR(*range_at(caster, 2.0), 7.0, 1e-9);
  // Changes come in device-time order; the refused one changes nothing.
  EXPECT_TRUE(!caster.add_object(box("late", 3.0), 1.7).has_value());
  EXPECT_TRUE(!caster.remove_object("crate", 3.0).has_value()) << "removed already";
  EXPECT_TRUE(!caster.add_object(box("wall", 3.0), 3.0).has_value()) << "the name is taken";
  EXPECT_TRUE(!caster.remove_object("wall", 1.9).has_value()) << "before the last change";
  ASSERT_EQ(caster.remove_object("wall", 3.0).value(), 3.0);
  EXPECT_EQ(caster.static_epochs(), 3u);
  EXPECT_FALSE(range_at(caster, 3.0)) << "nothing left ahead";
  caster.prepare(1.6, 1.7);
  EXPECT_EQ(caster.static_epochs(), 2u) << "the epoch before 1.5 s can no longer be asked for";
  EXPECT_NEAR(*range_at(caster, 2.55), 7.0, 1e-9);
  caster.prepare(3.5, 3.6);
  EXPECT_EQ(caster.static_epochs(), 1u);
}

TEST(RuntimeChanges, MovingObjectsAddedAndRemovedExistOnlyInBetween) {
  SceneCaster caster(scene_from("objects:\n  - name: wall\n    box: {size_m: [0.5, 10, 5]}\n    pose: {position_m: [10.25, 0, 0]}\n"));
  scene::SceneObject walker = box("walker", 4.25);
  walker.pose.position_m.y() = -1.0;
  walker.motion = scene::ConstantVelocity{Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::Zero()};  // y = -1 + t
  ASSERT_EQ(caster.add_object(walker, 1.0).value(), 1.0);
  ASSERT_EQ(caster.remove_object("walker", 3.5).value(), 3.5);
  for (const double t : {0.5, 1.5, 2.5, 3.4, 3.6}) {
    caster.prepare(t - 0.05, t + 0.05);
    const bool there = t >= 1.0 && t < 3.5 && std::abs(-1.0 + t) < 1.0;  // its 2 m face spans y +- 1
    EXPECT_NEAR(*range_at(caster, t), there ? 4.0 : 10.0, 1e-9) << "t " << t;
  }
  EXPECT_TRUE(!caster.move_object("walker", scene::Pose{}, 4.0, false).has_value())
      << "a removed object cannot be moved";
}

TEST(RuntimeChanges, RemovedBodyStopsCollidingAndIsNotSeen) {
  SceneCaster caster(scene_from("world: {world_step_s: 0.001}\n"
                                "objects:\n"
                                "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
                                "  - name: ball\n"
                                "    sphere: {radius_m: 0.5}\n"
                                "    pose: {position_m: [4, 0, 0.5]}\n"
                                "    dynamics: {mass_kg: 1}\n"));
  caster.prepare(0.0, 0.1);
  EXPECT_NEAR(*range_at(caster, 0.05), 3.5, 1e-6);
  ASSERT_TRUE(caster.remove_object("ball", 1.0).has_value());
  caster.prepare(1.2, 1.3);
  const auto hit = caster.cast(ray_at(Eigen::Vector3d(0, 0, 0.5), kAhead, 1.25));
  EXPECT_FALSE(hit) << "range " << (hit ? hit->range_m : 0.0);
}

}  // namespace
}  // namespace ldoem::world

namespace ldoem::world {
namespace {

// A closed cube of edge 1 m about its origin: 8 vertices, 12 triangles facing outwards.
scene::SceneObject runtime_cube_mesh(const std::string& name, double x) {
  scene::Mesh mesh;
  const auto corner = [](int i, int bit) { return (i & bit) != 0 ? 0.5f : -0.5f; };
  for (int i = 0; i < 8; ++i) mesh.vertices_m.emplace_back(corner(i, 1), corner(i, 2), corner(i, 4));
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  scene::SceneObject object;
  object.name = name;
  object.shape = std::move(mesh);
  object.pose.position_m = Eigen::Vector3d(x, 0, 0.5);
  return object;
}

// Issue 27 (D8): a mesh's ODE tree was built on the event loop's thread at every rebuild of the
// moving index (add-object, remove-object). The daemon now builds it on add-object's worker and
// hands it in; the index keeps it for later rebuilds, so this thread builds none.
TEST(RuntimeChanges, AMeshTreeBuiltElsewhereIsUsedAndKeptByLaterRebuilds) {
  SceneCaster caster(scene_from("objects:\n  - name: wall\n    box: {size_m: [0.5, 10, 5]}\n    pose: {position_m: [10.25, 0, 0]}\n"));
  const scene::SceneObject rock = runtime_cube_mesh("rock", 4.0);
  std::shared_ptr<const raycast::TriMeshData> tree;
  std::thread([&] { tree = raycast::TriMeshData::build(std::get<scene::Mesh>(rock.shape)); }).join();
  const std::uint64_t before = raycast::TriMeshData::built_on_this_thread();
  ASSERT_EQ(caster.add_object(rock, 1.0, tree).value(), 1.0);
  ASSERT_EQ(caster.add_object(box("crate", 7.25), 2.0).value(), 2.0);  // rebuilds the index
  ASSERT_EQ(caster.remove_object("crate", 3.0).value(), 3.0);          // and again
  EXPECT_EQ(raycast::TriMeshData::built_on_this_thread(), before) << "a rebuild built the mesh's tree again";
  EXPECT_NEAR(*range_at(caster, 1.5), 3.5, 1e-9) << "the tree built on another thread answers the rays";
  EXPECT_NEAR(*range_at(caster, 0.5), 10.0, 1e-9);
  // Without one, add_object builds it here (the daemon under --virtual-time), once.
  ASSERT_EQ(caster.add_object(runtime_cube_mesh("pebble", 2.0), 4.0).value(), 4.0);
  ASSERT_EQ(caster.remove_object("rock", 5.0).value(), 5.0);
  EXPECT_EQ(raycast::TriMeshData::built_on_this_thread(), before + 1);
  EXPECT_NEAR(*range_at(caster, 5.5), 1.5, 1e-9);
}

}  // namespace
}  // namespace ldoem::world
