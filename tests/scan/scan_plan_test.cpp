#include "ldoem/scan/scan_plan.hpp"

#include <gtest/gtest.h>

#include "ldoem/protocol/messages.hpp"

namespace ldoem::scan {
namespace {

using protocol::sector_function::kNoMeasurement;
using protocol::sector_function::kNormalMeasurement;

TEST(PlanSectors, DefaultApex_MeasuresOnlyTwentyDegreesAroundPlusX) {
  auto plan = plan_sectors(20.0, 0.25, 10);
  ASSERT_TRUE(plan) << plan.error();
  EXPECT_EQ(plan->angle_step_ticks, 4);
  ASSERT_EQ(plan->sectors.size(), 2u);
  // Sector 0 from -10 deg (5600 ticks) through 0 to +10 deg (160); sector 1 blanks the rest.
  EXPECT_EQ(plan->sectors[0], (driver::SectorDefinition{kNormalMeasurement, 160}));
  EXPECT_EQ(plan->sectors[1], (driver::SectorDefinition{kNoMeasurement, 5596}));
  EXPECT_EQ(plan->beams_per_profile, 81u);
  EXPECT_DOUBLE_EQ(plan->max_pulse_frequency_hz, 14400.0);
  // Spec 5: area = stop - previous stop = 160 + 164 ticks.
  EXPECT_DOUBLE_EQ(plan->mean_pulse_frequency_hz, 14400.0 * 324.0 / 5760.0);
}

TEST(PlanSectors, MaxPulseRule_RefusesFineStepAtHighSpeed) {
  EXPECT_FALSE(plan_sectors(20.0, 0.25, 20));  // 28 800 Hz > 14 400 Hz
  EXPECT_TRUE(plan_sectors(20.0, 0.5, 20));
}

TEST(PlanSectors, MeanPulseRule_RefusesWideApexAtTheLimit) {
  // 0.125 deg at 5 Hz is 14 400 Hz max; 300 deg measured is 12 000 Hz mean > 10 800 Hz.
  EXPECT_FALSE(plan_sectors(300.0, 0.125, 5));
  EXPECT_TRUE(plan_sectors(200.0, 0.125, 5));
}

TEST(PlanSectors, OffGridValues_AreRefused) {
  EXPECT_FALSE(plan_sectors(20.0, 0.3, 10));    // 4.8 ticks
  EXPECT_FALSE(plan_sectors(20.0, 0.0625, 5));  // below the 0.125 deg granule
  EXPECT_FALSE(plan_sectors(20.1, 0.25, 10));   // half apex off the step grid
  EXPECT_FALSE(plan_sectors(20.0, 0.25, 4));    // speed below 5 Hz
  EXPECT_FALSE(plan_sectors(359.75, 0.25, 5));  // no room for the blanked sector
}

TEST(PlanLayers, Defaults_Give121LayersOfTwoFullSteps) {
  auto plan = plan_layers(21.6, 0.18, false);
  ASSERT_TRUE(plan) << plan.error();
  EXPECT_EQ(plan->layer_count, 121u);
  EXPECT_EQ(plan->steps_per_layer, 2u);
  EXPECT_EQ(plan->start_steps, -120);
  EXPECT_EQ(plan->layer_half_steps(0), -240);
  EXPECT_EQ(plan->layer_half_steps(120), 240);
  EXPECT_NEAR(plan->layer_tilt_deg(0), -10.8, 1e-9);
  EXPECT_NEAR(plan->layer_tilt_deg(60), 0.0, 1e-12);
}

TEST(PlanLayers, HalfStep_UsesFourHalfStepsPerLayer) {
  auto plan = plan_layers(21.6, 0.18, true);
  ASSERT_TRUE(plan) << plan.error();
  EXPECT_EQ(plan->steps_per_layer, 4u);
  EXPECT_EQ(plan->layer_half_steps(0), -240);
  auto fine = plan_layers(0.9, 0.045, true);
  ASSERT_TRUE(fine);
  EXPECT_EQ(fine->layer_count, 21u);
}

TEST(PlanLayers, ResolutionOffTheStepGrid_IsAnError) {
  EXPECT_FALSE(plan_layers(21.6, 0.1, false));
  EXPECT_FALSE(plan_layers(21.6, 0.045, false));  // half a full step
  EXPECT_FALSE(plan_layers(21.6, 0.0, false));
  EXPECT_FALSE(plan_layers(-1.0, 0.18, false));
}

TEST(PlanLayers, ZeroApex_IsOneLevelLayer) {
  auto plan = plan_layers(0.0, 0.18, false);
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->layer_count, 1u);
  EXPECT_EQ(plan->layer_half_steps(0), 0);
}

TEST(PlanLayers, OddStepTotal_StartsHalfAStepHigh) {
  auto plan = plan_layers(0.27, 0.09, false);  // 4 layers, 3 steps in all
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->layer_count, 4u);
  EXPECT_EQ(plan->start_steps, -1);
  EXPECT_EQ(plan->layer_half_steps(3), 4);
}

}  // namespace
}  // namespace ldoem::scan
