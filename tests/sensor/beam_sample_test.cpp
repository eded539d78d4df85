#include <ldoem/sensor/beam_sample.hpp>
#include <ldoem/scene/optics.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ldoem::sensor {
namespace {

constexpr RangeLimits kLimits{.min_range_m = 0.9, .max_range_m = 30.0};

TEST(QuantiseRange, ExactMultiple_EncodesUnits) {
  EXPECT_EQ(quantise_range(5.0, kLimits), std::optional<std::uint16_t>(1280));
  EXPECT_EQ(quantise_range(1.0 + 1.0 / 256, kLimits), std::optional<std::uint16_t>(257));
}

TEST(QuantiseRange, RoundsToNearestSixteenth) {
  EXPECT_EQ(quantise_range(5.0 + 0.49 / 256, kLimits), std::optional<std::uint16_t>(1280));
  EXPECT_EQ(quantise_range(5.0 + 0.51 / 256, kLimits), std::optional<std::uint16_t>(1281));
}

TEST(QuantiseRange, BelowMinimum_NoEcho) { EXPECT_FALSE(quantise_range(0.85, kLimits)); }
TEST(QuantiseRange, AboveMaximum_NoEcho) { EXPECT_FALSE(quantise_range(30.01, kLimits)); }
TEST(QuantiseRange, ExactlyAtLimits_Kept) {
  EXPECT_EQ(quantise_range(30.0, kLimits), std::optional<std::uint16_t>(7680));
  EXPECT_EQ(quantise_range(0.90, kLimits), std::optional<std::uint16_t>(230));  // limits before rounding
  EXPECT_FALSE(quantise_range(0.8999, kLimits));
}
TEST(QuantiseRange, NaN_NoEcho) { EXPECT_FALSE(quantise_range(std::nan(""), kLimits)); }
TEST(QuantiseRange, Infinity_NoEcho) {
  EXPECT_FALSE(quantise_range(std::numeric_limits<double>::infinity(), kLimits));
  EXPECT_FALSE(quantise_range(-std::numeric_limits<double>::infinity(), kLimits));
}
TEST(QuantiseRange, NegativeOrZero_NoEcho) {
  const RangeLimits no_minimum{.min_range_m = 0.0, .max_range_m = 255.99};
  EXPECT_FALSE(quantise_range(0.0, no_minimum));
  EXPECT_FALSE(quantise_range(-1.0, no_minimum));
}
TEST(QuantiseRange, ProtocolMaximum_FitsSixteenBits) {
  const RangeLimits widest{.min_range_m = 0.9, .max_range_m = 255.99};
  EXPECT_EQ(quantise_range(255.99, widest), std::optional<std::uint16_t>(65533));
  EXPECT_FALSE(quantise_range(256.0, widest));
}

TEST(Irradiance, CalibratedOptics_GiveThePapersMaximumRange) {
  scene::OpticsConfig optics;
  optics.calibration = scene::calibration_for_max_range(optics, 63.1);
  EXPECT_NEAR(scene::max_detectable_range(optics, 1.0, 1.0), 63.1, 1e-9);
  EXPECT_NEAR(scene::max_detectable_range(optics, 0.25, 1.0), 63.1 * 0.5, 1e-9);  // l_max = 63.1 sqrt(r cos a)
  EXPECT_NEAR(scene::received_irradiance(optics, 1.0, 1.0, 63.1), optics.min_irradiance, 1e-15);
}

TEST(Irradiance, InverseSquareAndLambert) {
  scene::OpticsConfig optics;
  optics.calibration = scene::calibration_for_max_range(optics, 63.1);
  const double at_10m = scene::received_irradiance(optics, 0.8, 1.0, 10.0);
  EXPECT_NEAR(scene::received_irradiance(optics, 0.8, 1.0, 20.0), at_10m / 4, 1e-15);
  EXPECT_NEAR(scene::received_irradiance(optics, 0.8, 0.5, 10.0), at_10m / 2, 1e-15);
  EXPECT_NEAR(scene::received_irradiance(optics, 0.4, 1.0, 10.0), at_10m / 2, 1e-15);
}

TEST(Irradiance, DegenerateInputs_GiveZeroNotNaN) {
  scene::OpticsConfig optics;
  EXPECT_TRUE(std::isfinite(scene::received_irradiance(optics, 1.0, 1.0, 0.0)));  // clamped range
  EXPECT_EQ(scene::received_irradiance(optics, 1.0, 1.0, std::nan("")), 0.0);
  EXPECT_EQ(scene::received_irradiance(optics, 1.0, std::nan(""), 1.0), 0.0);
  EXPECT_EQ(scene::received_irradiance(optics, 1.0, 0.0, 1.0), 0.0);    // grazing
  EXPECT_EQ(scene::received_irradiance(optics, 1.0, -0.5, 1.0), 0.0);   // back face
  EXPECT_TRUE(std::isfinite(scene::received_irradiance(optics, 1.0, 1.0, 1e-300)));  // no overflow
}

}  // namespace
}  // namespace ldoem::sensor
