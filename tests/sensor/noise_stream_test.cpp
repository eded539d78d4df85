#include <ldoem/sensor/noise_stream.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace ldoem::sensor {
namespace {

TEST(NoiseStream, Construction_DrawsNothing) {
  const NoiseStream stream(NoiseKey{.seed = 7, .revolution = 1, .beam_index = 2});
  EXPECT_EQ(stream.draws(), 0u);
}

TEST(NoiseStream, NormalValue_CountsTwoDraws) {
  NoiseStream stream(NoiseKey{.seed = 7});
  (void)stream.standard_normal();
  EXPECT_EQ(stream.draws(), 2u);
}

TEST(NoiseStream, SameKey_SameSequence) {
  NoiseStream first(NoiseKey{.seed = 42, .revolution = 3, .beam_index = 99, .sub_stream = 1});
  NoiseStream second(NoiseKey{.seed = 42, .revolution = 3, .beam_index = 99, .sub_stream = 1});
  for (int i = 0; i < 100; ++i) EXPECT_EQ(first.next_bits(), second.next_bits());
}

TEST(NoiseStream, AnyKeyFieldChanged_DifferentFirstWord) {
  const NoiseKey base{.seed = 42, .revolution = 3, .beam_index = 99, .sub_stream = 0};
  std::set<std::uint64_t> firsts;
  for (NoiseKey key : {base, NoiseKey{43, 3, 99, 0}, NoiseKey{42, 4, 99, 0}, NoiseKey{42, 3, 100, 0},
                       NoiseKey{42, 3, 99, 1}, NoiseKey{42, 99, 3, 0}}) {
    firsts.insert(NoiseStream(key).next_bits());
  }
  EXPECT_EQ(firsts.size(), 6u);
}

TEST(NoiseStream, Uniform_StaysInOpenClosedUnitInterval) {
  NoiseStream stream(NoiseKey{.seed = 5});
  double lowest = 1.0;
  for (int i = 0; i < 100000; ++i) {
    const double value = stream.uniform_open_closed();
    ASSERT_GT(value, 0.0);
    ASSERT_LE(value, 1.0);
    lowest = std::min(lowest, value);
  }
  EXPECT_LT(lowest, 1e-3);  // the low end is reached, not clipped
}

// One normal per beam, as the noise effect draws them: 1e5 beams over 100 revolutions, fixed
// seed. Tolerances: mean within 0.015 (~4.7 standard errors of 1/sqrt(1e5)), sigma within 0.01
// (~4.5 standard errors of 1/sqrt(2e5)). The seed is fixed, so this cannot flake.
TEST(NoiseStream, NormalsAcrossBeams_HaveUnitStatistics) {
  constexpr int kRevolutions = 100;
  constexpr int kBeams = 1000;
  double sum = 0.0;
  double sum_sq = 0.0;
  double lag_product = 0.0;
  double previous = 0.0;
  for (std::uint32_t revolution = 0; revolution < kRevolutions; ++revolution) {
    for (std::uint32_t beam = 0; beam < kBeams; ++beam) {
      NoiseStream stream(NoiseKey{.seed = 2024, .revolution = revolution, .beam_index = beam});
      const double value = stream.standard_normal();
      ASSERT_TRUE(std::isfinite(value));
      sum += value;
      sum_sq += value * value;
      lag_product += value * previous;
      previous = value;
    }
  }
  const double count = kRevolutions * kBeams;
  const double mean = sum / count;
  const double sigma = std::sqrt(sum_sq / count - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.015);
  EXPECT_NEAR(sigma, 1.0, 0.01);
  EXPECT_NEAR(lag_product / count, 0.0, 0.015);  // neighbouring beams are uncorrelated
}

}  // namespace
}  // namespace ldoem::sensor
