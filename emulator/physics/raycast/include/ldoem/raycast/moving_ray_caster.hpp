// D12: the caster for objects that move. Each ray carries its instant (Ray::time_s) and meets
// every moving object at its pose of that instant, exactly (ODE's dCollide on the object's shape,
// the ray taken into the object's frame). An Embree index over boxes that hold each object for a
// whole time window finds the candidates; it is built once per window (prepare), never per
// beam. Static objects stay in EmbreeRayCaster; world::SceneCaster combines the two.
//
// Two indices, chosen by MovingCasterOptions (docs/dynamic-scenes.md has the measurements):
// - swept_slices: the window is cut into `slices` equal slices, each with its own BVH of boxes
//   swept over that slice, built afresh (or refitted, `refit`) on prepare; a ray uses the slice
//   of its time.
// - motion_blur: one Embree BVH with `slices` + 1 motion-blur time steps, the ray's time
//   normalised over the window; Embree interpolates the boxes between steps.
#pragma once

#include "ldoem/raycast/ray_caster.hpp"
#include "ldoem/scene/scene.hpp"

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace ldoem::raycast {

class TriMeshData;  // ode_world.hpp

// Where each moving object is. Implemented by emulator/physics/world (kinematic paths, ODE bodies).
// Const calls must be thread-safe.
class MotionSource {
 public:
  virtual ~MotionSource() = default;
  // Pose of moving object k at time t.
  virtual scene::Pose pose_at(std::size_t k, double t_s) const = 0;
  // Its origin only; sources override it when that is cheaper than the whole pose (a candidate
  // is first tested against the sphere about its origin, which needs no orientation).
  virtual Eigen::Vector3d position_at(std::size_t k, double t_s) const { return pose_at(k, t_s).position_m; }
  // A box holding object k's origin for every t in [t0, t1].
  virtual scene::PathBounds origin_bounds(std::size_t k, double t0_s, double t1_s) const = 0;
  // True if object k never turns (its box then keeps its axis-aligned extent).
  virtual bool keeps_orientation(std::size_t k) const = 0;
  // If object k turns only about one fixed axis through its origin (a constant spin), that axis
  // (unit, world frame): its box is then the cylinder about the axis, tighter than the sphere
  // that holds any orientation. Nothing otherwise.
  virtual std::optional<Eigen::Vector3d> spin_axis(std::size_t /*k*/) const { return std::nullopt; }
};

// When a moving object exists: rays timed in [from_s, until_s) see it (runtime add-object and
// remove-object, docs/dynamic-scenes.md "Runtime changes").
struct TimeSpan {
  double from_s = -INFINITY;
  double until_s = INFINITY;
};

enum class MovingIndex : std::uint8_t { swept_slices, motion_blur };

struct MovingCasterOptions {
  MovingIndex index = MovingIndex::swept_slices;
  // One slice: chosen by BM_MovingObjects (docs/dynamic-scenes.md "Cost"); more slices give
  // tighter boxes but each costs a build per window, which outweighed the saving.
  unsigned slices = 1;  // slices per window (swept_slices) or motion-blur segments (motion_blur)
  // prepare() readies at least this long a window and is free while later batches fall inside
  // it: an Embree commit costs about 0.1 ms however few the boxes, so covering several
  // revolutions with one (looser) index can pay. 0: exactly the window asked for. The default,
  // three revolutions at 10 Hz, measured best (docs/dynamic-scenes.md "Cost").
  double min_window_s = 0.3;
  // Refit the BVH of the last full build on prepare (a full build every 64 windows) instead of
  // building it afresh. A refit is a little cheaper per window, but it keeps the tree's leaves,
  // and Embree hands every box of a leaf it reaches to the intersect callback without testing
  // the box: with boxes that moved since the build, a ray meets several times as many candidates
  // as after a fresh build, which costs more than the build saves (docs/dynamic-scenes.md "Cost").
  bool refit = false;
};

class MovingRayCaster final : public RayCaster {
 public:
  // objects[k] is moving object k (its pose and motion are ignored: poses come from `motion`);
  // hits report scene_indices[k]. `motion` must outlive the caster. meshes[k], when given and
  // not null, is mesh object k's trimesh data, built beforehand (OdeWorld): a caster rebuilt at
  // a runtime change then builds no mesh's tree again, which is most of its cost.
  MovingRayCaster(const std::vector<scene::SceneObject>& objects, std::vector<std::uint32_t> scene_indices,
                  const MotionSource& motion, MovingCasterOptions options = {},
                  std::vector<std::shared_ptr<const TriMeshData>> meshes = {});
  ~MovingRayCaster() override;
  MovingRayCaster(const MovingRayCaster&) = delete;
  MovingRayCaster& operator=(const MovingRayCaster&) = delete;

  // Readies the index for rays timed in [t0, t1] (t1 > t0), or keeps the current one if it
  // already covers them (see min_window_s). Not thread-safe: call it between
  // batches of casts. A ray timed outside the prepared window is still answered exactly, by
  // testing every moving object (slower, never wrong).
  void prepare(double t0_s, double t1_s);
  // Forgets the prepared window: the next prepare rebuilds (after a runtime move).
  void invalidate();
  // spans[k]: when object k exists (one per object; empty: always, as built). Call between batches.
  void set_presence(std::vector<TimeSpan> spans);

  // Const and thread-safe between prepare calls.
  std::optional<Hit> cast(const Ray& ray) const override;

  std::size_t object_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::raycast
