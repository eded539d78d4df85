// D6 optics: the calibration reproduces l_max = 63.1 m sqrt(r cos alpha); guards never give NaN.
#include "ldoem/scene/optics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ldoem::scene {
namespace {

OpticsConfig calibrated() {
  OpticsConfig optics;
  optics.calibration = calibration_for_max_range(optics, optics.max_range_at_full_reflectance_m);
  return optics;
}

TEST(Optics, WhiteTargetHeadOnAtMaxRange_IsExactlyThreshold) {
  const OpticsConfig optics = calibrated();
  const double irradiance = received_irradiance(optics, 1.0, 1.0, 63.1);
  EXPECT_NEAR(irradiance / optics.min_irradiance, 1.0, 1e-12);
}

TEST(Optics, MaxRange_ScalesWithSqrtOfReflectanceTimesCos) {
  const OpticsConfig optics = calibrated();
  for (double r : {0.1, 0.5, 0.9}) {
    for (double cos_alpha : {0.05, 0.5, 1.0}) {
      const double l_max = max_detectable_range(optics, r, cos_alpha);
      EXPECT_NEAR(l_max, 63.1 * std::sqrt(r * cos_alpha), 1e-9);
      EXPECT_NEAR(received_irradiance(optics, r, cos_alpha, l_max) / optics.min_irradiance, 1.0, 1e-12);
    }
  }
}

TEST(Optics, PaperConstantsInCentimetres_GiveThePaperRange) {
  // The paper's numbers (d = 4 with l in metres, no calibration) drop out at 63.08 m: the
  // default 63.1 m is that value rounded (D6).
  OpticsConfig paper;
  paper.receiver_diameter_m = 4.0;
  paper.calibration = 1.0;
  EXPECT_NEAR(max_range_at_full_reflectance(paper), 63.08, 0.01);
}

TEST(Optics, InverseSquareInRange) {
  const OpticsConfig optics = calibrated();
  EXPECT_NEAR(received_irradiance(optics, 0.5, 0.7, 2.0) / received_irradiance(optics, 0.5, 0.7, 4.0), 4.0, 1e-12);
}

TEST(Optics, EdgeInputs_NeverNanOrInf) {
  const OpticsConfig optics = calibrated();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(received_irradiance(optics, nan, 1.0, 1.0), 0.0);
  EXPECT_EQ(received_irradiance(optics, 1.0, inf, 1.0), 0.0);
  EXPECT_EQ(received_irradiance(optics, 1.0, 1.0, inf), 0.0);
  EXPECT_EQ(received_irradiance(optics, 1.0, -0.5, 10.0), 0.0);  // back-facing: no light
  EXPECT_TRUE(std::isfinite(received_irradiance(optics, 1.0, 1.0, 0.0)));
  EXPECT_TRUE(std::isfinite(received_irradiance(optics, 1.0, 1.0, -1.0)));
  // Above 1 only a retro-reflector's optical reflectance is legal; beyond its gain it is clamped.
  EXPECT_EQ(received_irradiance(optics, 1e6, 1.0, 10.0), received_irradiance(optics, kRetroReflectiveGain, 1.0, 10.0));
  EXPECT_EQ(max_detectable_range(optics, nan, 1.0), 0.0);
}

TEST(Optics, EchoValue_FollowsD6AndSaturates) {
  const OpticsConfig optics = calibrated();
  EXPECT_EQ(echo_value(optics, optics.min_irradiance), 1000);
  EXPECT_EQ(echo_value(optics, optics.min_irradiance * 2.5), 2500);
  EXPECT_EQ(echo_value(optics, optics.min_irradiance * 1000.0), 65535);
  EXPECT_EQ(echo_value(optics, std::numeric_limits<double>::infinity()), 0);
  EXPECT_EQ(echo_value(optics, -1.0), 0);
}

}  // namespace
}  // namespace ldoem::scene
