// D9 mixed_pixels: the beam is not a line but a cone of full angle beam_divergence_rad. It is
// sampled by sub-rays on hexagonal rings (1, 7, 19, 37), each standing for an equal share of the
// beam's cross-section (a top-hat profile). The measured range is the irradiance-weighted mean
// of the sub-rays' ranges, so a beam straddling an edge reports a range between the two surfaces,
// nearer the one that returns more power: the artefact real scans show at depth steps.
#include "footprint.hpp"
#include "hit_geometry.hpp"
#include "received_power.hpp"

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

class MixedPixelsStage final : public BeamStage {
 public:
  MixedPixelsStage(double beam_divergence_rad, int subray_count, const detail::ReceivedPower& power)
      : beam_divergence_rad_(beam_divergence_rad),
        offsets_(hexagonal_subray_offsets(beam_divergence_rad, subray_count)),
        power_(power) {}

  std::string_view name() const override { return "mixed_pixels"; }

  std::string describe() const override {
    std::ostringstream text;
    text << "mixed_pixels: " << offsets_.size() << " sub-rays, divergence " << beam_divergence_rad_
         << " rad, incidence " << (power_.use_incidence() ? "on" : "off");
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const override {
    detail::FootprintCast cast;  // fixed bound (37 sub-rays): allocation-free
    detail::cast_footprint(beam.ray, offsets_, context.caster, cast);
    counters.rays_cast += cast.count;
    combine(beam, cast.ray_span(), cast.hit_span());
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
      const double irradiance = power_(hit.reflectance, cosine, hit.range_m);
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
  detail::ReceivedPower power_;
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
                                                   const scene::OpticsConfig& optics, bool use_incidence,
                                                   const std::optional<scene::AtmosphereConfig>& atmosphere) {
  return std::make_unique<MixedPixelsStage>(beam_divergence_rad, subray_count,
                                            detail::ReceivedPower(optics, use_incidence, atmosphere));
}

}  // namespace ldoem::sensor
