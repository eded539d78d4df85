// Sector table geometry and the TRANS_MEASURE checks (spec 3.6, spec 5, lead decision 1).
#include <gtest/gtest.h>

#include "ldoem/control/device_config.hpp"
#include "ldoem/control/sector_table.hpp"

namespace ldoem::control {
namespace {

constexpr std::uint16_t kNone = 0, kBlank = 1, kNormal = 3, kReference = 4;

SectorTable table_of(std::initializer_list<Sector> sectors) {
  SectorTable table{};
  std::size_t i = 0;
  for (const Sector& sector : sectors) table[i++] = sector;
  return table;
}

TEST(SectorTable, D4Defaults_PassExactlyAtTheMeanLimit) {
  const DeviceConfig config = factory_config();
  EXPECT_EQ(check_measure_configuration(config.sectors, 4, 10), MeasureCheck::ok);
  // One more Hz and the mean pulse frequency (11 * 4320 / 4 = 11880 Hz) is over 10800, while
  // the max (1440 * 11 = 15840) is over 14400 first: code 1 wins by the check order.
  EXPECT_EQ(check_measure_configuration(config.sectors, 4, 11), MeasureCheck::max_pulse_frequency_too_high);
}

TEST(SectorTable, D4Defaults_GeometryWrapsSectorZeroThroughZeroDegrees) {
  const auto geometry = sector_geometry(factory_config().sectors, 4);
  ASSERT_EQ(geometry.size(), 2u);
  EXPECT_EQ(geometry[0].first_angle_unwrapped_ticks, 3604u);  // one step after sector 1's stop
  EXPECT_EQ(geometry[0].last_angle_unwrapped_ticks, 5760u + 2160u);
  EXPECT_EQ(wrap_angle(geometry[0].last_angle_unwrapped_ticks), 2160);
  EXPECT_EQ(geometry[0].point_count, 1080u);  // (2160 - 3604) mod 5760 / 4 + 1
  EXPECT_EQ(geometry[1].first_angle_unwrapped_ticks, 5760u + 2164u);
  EXPECT_EQ(geometry[1].last_angle_unwrapped_ticks, 5760u + 3600u);
  EXPECT_EQ(geometry[1].point_count, 0u);  // no measurement: POINTNUM 0 (D3)
}

TEST(SectorTable, S1ActiveAreasExample_IsValid) {
  // Spec 3.6: s0 normal 270 deg, s1 blank 314.5, s2 normal 45, s3 blank 89.5, s4 terminator.
  const SectorTable table =
      table_of({{kNormal, 4320}, {kBlank, 5032}, {kNormal, 720}, {kBlank, 1432}, {kNone, 0}});
  EXPECT_EQ(check_measure_configuration(table, 8, 10), MeasureCheck::ok);
  const auto geometry = sector_geometry(table, 8);
  ASSERT_EQ(geometry.size(), 4u);
  EXPECT_EQ(geometry[0].first_angle_unwrapped_ticks, 1440u);  // 90 deg
  EXPECT_EQ(geometry[0].point_count, 361u);                   // 90..270 deg at 0.5 deg
  EXPECT_EQ(wrap_angle(geometry[2].first_angle_unwrapped_ticks), 5040);  // 315 deg
  EXPECT_EQ(wrap_angle(geometry[2].last_angle_unwrapped_ticks), 720);
  EXPECT_EQ(geometry[2].point_count, 181u);
  EXPECT_EQ(geometry[3].last_angle_unwrapped_ticks, 1440u + 5760u - 8u);
}

TEST(SectorTable, SingleSector_SpansTheWholeTurn) {
  const SectorTable table = table_of({{kNormal, 5744}});  // S2: 359 deg at 0.5 deg
  // 20 Hz: max 720 * 20 = 14400 is allowed, the mean over the full turn is the same: too high.
  EXPECT_EQ(check_measure_configuration(table, 8, 20), MeasureCheck::mean_pulse_frequency_too_high);
  EXPECT_EQ(check_measure_configuration(table, 8, 16), MeasureCheck::mean_pulse_frequency_too_high);
  EXPECT_EQ(check_measure_configuration(table, 8, 15), MeasureCheck::ok);  // 10800 Hz: at the limit
  EXPECT_EQ(check_measure_configuration(table, 8, 10), MeasureCheck::ok);  // 7200 Hz
  const auto geometry = sector_geometry(table, 8);
  ASSERT_EQ(geometry.size(), 1u);
  EXPECT_EQ(geometry[0].point_count, 720u);
  EXPECT_EQ(geometry[0].first_angle_unwrapped_ticks, 5752u);
}

TEST(SectorTable, SectorsAfterTheFirstTerminatorAreIgnored) {
  SectorTable table = table_of({{kNormal, 2160}, {kBlank, 3600}, {kNone, 0}, {kNormal, 100}});
  EXPECT_EQ(initialised_sector_count(table), 2u);
  EXPECT_EQ(check_measure_configuration(table, 4, 10), MeasureCheck::ok);
}

struct CheckCase {
  const char* name;
  SectorTable table;
  std::uint16_t step;
  std::uint16_t speed_hz;
  MeasureCheck expected;
};

void PrintTo(const CheckCase& c, std::ostream* os) { *os << c.name; }

class MeasureCheckTable : public ::testing::TestWithParam<CheckCase> {};

TEST_P(MeasureCheckTable, ReturnsTheCodeOfTheFirstFailingCheck) {
  const CheckCase& c = GetParam();
  EXPECT_EQ(check_measure_configuration(c.table, c.step, c.speed_hz), c.expected) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Codes, MeasureCheckTable,
    ::testing::Values(
        CheckCase{"empty", table_of({}), 8, 10, MeasureCheck::sector_borders_not_configured},
        CheckCase{"no_measuring", table_of({{kBlank, 5760}}), 8, 10, MeasureCheck::sector_borders_not_configured},
        CheckCase{"stop_over_5760", table_of({{kNormal, 2000}, {kBlank, 5768}}), 8, 5,
                  MeasureCheck::sector_borders_not_configured},
        CheckCase{"zero_span", table_of({{kNormal, 2000}, {kBlank, 2000}, {kBlank, 4000}}), 8, 5,
                  MeasureCheck::sector_borders_not_configured},
        CheckCase{"out_of_order_two_turns", table_of({{kNormal, 1440}, {kBlank, 720}, {kBlank, 4320}}), 8, 5,
                  MeasureCheck::sector_borders_not_configured},
        CheckCase{"not_multiple_of_step", table_of({{kNormal, 2161}, {kBlank, 3600}}), 4, 10,
                  MeasureCheck::sector_borders_not_multiple_of_step},
        CheckCase{"max_pulse_before_borders", table_of({}), 2, 10, MeasureCheck::max_pulse_frequency_too_high},
        CheckCase{"borders_before_mean", table_of({{kNormal, 5760}, {kNormal, 5760}}), 8, 20,
                  MeasureCheck::sector_borders_not_configured},
        CheckCase{"step_before_mean", table_of({{kNormal, 5756}}), 8, 20,
                  MeasureCheck::sector_borders_not_multiple_of_step},
        CheckCase{"mean_too_high", table_of({{kNormal, 5760}}), 8, 20, MeasureCheck::mean_pulse_frequency_too_high},
        CheckCase{"reference_counts_as_measuring", table_of({{kReference, 2880}, {kBlank, 5760}}), 8, 20,
                  MeasureCheck::ok},
        CheckCase{"20hz_half_degree_limit", table_of({{kNormal, 4320}, {kBlank, 5760}}), 8, 20, MeasureCheck::ok},
        CheckCase{"20hz_quarter_degree", table_of({{kNormal, 4320}, {kBlank, 5760}}), 4, 20,
                  MeasureCheck::max_pulse_frequency_too_high},
        CheckCase{"5hz_eighth_degree_full_turn", table_of({{kNormal, 5760}}), 2, 5,
                  MeasureCheck::mean_pulse_frequency_too_high},
        CheckCase{"6hz_eighth_degree", table_of({{kNormal, 4320}, {kBlank, 5760}}), 2, 6,
                  MeasureCheck::max_pulse_frequency_too_high},
        CheckCase{"5hz_eighth_degree_three_quarters", table_of({{kNormal, 4320}, {kBlank, 5760}}), 2, 5,
                  MeasureCheck::ok}),
    [](const ::testing::TestParamInfo<CheckCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace ldoem::control
