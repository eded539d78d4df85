// D9 mixed_pixels: the beam is not a line but a cone of full angle beam_divergence_rad. It is
// sampled by sub-rays on hexagonal rings (1, 7, 19, 37), each standing for an equal share of the
// beam's cross-section (a top-hat profile). The measured range is the irradiance-weighted mean
// of the sub-rays' ranges, so a beam straddling an edge reports a range between the two surfaces,
// nearer the one that returns more power: the artefact real scans show at depth steps.
#include "hit_geometry.hpp"

#include <ldoem/sensor/effects.hpp>
#include <ldoem/scene/optics.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ldoem::sensor {
namespace {

int rings_for(int subray_count) {
  int rings = 0;
  while (rings < 3 && hexagonal_subray_count(rings + 1) <= subray_count) ++rings;
  return rings;
}

// Two unit vectors perpendicular to the direction and to each other, chosen deterministically
// (only their plane matters for a rotationally symmetric beam).
std::array<Eigen::Vector3d, 2> perpendicular_basis(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d helper =
      std::abs(direction.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d first = helper.cross(direction).normalized();
  return {first, direction.cross(first)};
}

class MixedPixelsStage final : public BeamStage {
 public:
  MixedPixelsStage(double beam_divergence_rad, int subray_count, const scene::OpticsConfig& optics,
                   bool use_incidence)
      : beam_divergence_rad_(beam_divergence_rad),
        offsets_(hexagonal_subray_offsets(beam_divergence_rad, subray_count)),
        optics_(optics),
        use_incidence_(use_incidence) {}

  std::string_view name() const override { return "mixed_pixels"; }

  std::string describe() const override {
    std::ostringstream text;
    text << "mixed_pixels: " << offsets_.size() << " sub-rays, divergence " << beam_divergence_rad_
         << " rad, incidence " << (use_incidence_ ? "on" : "off");
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const override {
    const std::size_t count = offsets_.size();
    // Small fixed bound (37) keeps this allocation-free.
    std::array<raycast::Ray, 37> rays;
    std::array<std::optional<raycast::Hit>, 37> hits;
    const auto [across, up] = perpendicular_basis(beam.ray.direction);
    for (std::size_t i = 0; i < count; ++i) {
      const Eigen::Vector2d& offset = offsets_[i];
      rays[i] = beam.ray;
      rays[i].direction =
          (beam.ray.direction + std::tan(offset.x()) * across + std::tan(offset.y()) * up).normalized();
    }
    context.caster.cast_many(std::span<const raycast::Ray>(rays.data(), count),
                             std::span<std::optional<raycast::Hit>>(hits.data(), count));
    counters.rays_cast += count;
    combine(beam, std::span<const raycast::Ray>(rays.data(), count),
            std::span<const std::optional<raycast::Hit>>(hits.data(), count));
  }

 private:
  void combine(BeamState& beam, std::span<const raycast::Ray> rays,
               std::span<const std::optional<raycast::Hit>> hits) const {
    double weight_sum = 0.0;
    double weighted_range_sum = 0.0;
    double plain_range_sum = 0.0;
    std::size_t hit_count = 0;
    double strongest = -1.0;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      if (!hits[i] || !detail::usable_hit(*hits[i])) continue;
      const raycast::Hit& hit = *hits[i];
      const double cosine = detail::cos_incidence(rays[i].direction, hit.normal);
      const double irradiance =
          scene::received_irradiance(optics_, hit.reflectance, use_incidence_ ? cosine : 1.0, hit.range_m);
      weight_sum += irradiance;
      weighted_range_sum += irradiance * hit.range_m;
      plain_range_sum += hit.range_m;
      ++hit_count;
      if (irradiance > strongest) {
        strongest = irradiance;
        beam.cos_incidence = cosine;
        beam.reflectance = hit.reflectance;
      }
    }
    if (hit_count == 0) {
      beam.has_return = false;
      return;
    }
    beam.has_return = true;
    // With no power anywhere (black or grazing targets) fall back to the plain mean: without
    // `intensity` such a beam still returns, exactly as it would without mixed_pixels.
    beam.range_m = weight_sum > 0.0 ? weighted_range_sum / weight_sum
                                    : plain_range_sum / static_cast<double>(hit_count);
    // The receiver collects the beam's share of power that came back: misses contribute 0.
    beam.irradiance = weight_sum / static_cast<double>(hits.size());
  }

  double beam_divergence_rad_;
  std::vector<Eigen::Vector2d> offsets_;
  scene::OpticsConfig optics_;
  bool use_incidence_;
};

}  // namespace

std::vector<Eigen::Vector2d> hexagonal_subray_offsets(double beam_divergence_rad, int subray_count) {
  const int rings = rings_for(subray_count);
  std::vector<Eigen::Vector2d> offsets{Eigen::Vector2d::Zero()};
  if (rings == 0) return offsets;
  const double spacing_rad = 0.5 * beam_divergence_rad / rings;  // outer corners on the half angle
  std::array<Eigen::Vector2d, 6> corner_directions;
  for (int corner = 0; corner < 6; ++corner) {
    const double angle = corner * std::numbers::pi / 3.0;
    corner_directions[corner] = {std::cos(angle), std::sin(angle)};
  }
  for (int ring = 1; ring <= rings; ++ring) {
    for (int side = 0; side < 6; ++side) {
      const Eigen::Vector2d start = ring * corner_directions[side];
      const Eigen::Vector2d step = corner_directions[(side + 2) % 6];  // along the hexagon's side
      for (int along = 0; along < ring; ++along) offsets.push_back(spacing_rad * (start + along * step));
    }
  }
  return offsets;
}

std::unique_ptr<BeamStage> make_mixed_pixels_stage(double beam_divergence_rad, int subray_count,
                                                   const scene::OpticsConfig& optics, bool use_incidence) {
  return std::make_unique<MixedPixelsStage>(beam_divergence_rad, subray_count, optics, use_incidence);
}

}  // namespace ldoem::sensor
