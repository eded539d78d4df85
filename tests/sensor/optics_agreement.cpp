#include <ldoem/scene/optics.hpp>
#include <ldoem/sensor/beam_sample.hpp>
#include <ldoem/sensor/irradiance.hpp>

#include <gtest/gtest.h>

namespace ldoem::sensor {
namespace {

TEST(OpticsAgreement, SensorAndSceneFormulas_GiveTheSameNumbers) {
  scene::OpticsConfig optics;
  optics.calibration = sensor::calibration_for_max_range(optics);
  EXPECT_DOUBLE_EQ(optics.calibration, scene::calibration_for_max_range(optics, 63.1));
  for (double range_m : {0.9, 5.0, 30.0, 63.1, 200.0}) {
    for (double reflectance : {0.05, 0.5, 1.0}) {
      for (double cosine : {0.01, 0.5, 1.0}) {
        const double ours = sensor::received_irradiance(optics, reflectance, cosine, range_m);
        EXPECT_DOUBLE_EQ(ours, scene::received_irradiance(optics, reflectance, cosine, range_m));
        EXPECT_EQ(echo_from_irradiance(ours, optics.min_irradiance), scene::echo_value(optics, ours));
      }
    }
  }
}

}  // namespace
}  // namespace ldoem::sensor
