// D14: SET_FILTER near-field suppression changes the profiles: on, points nearer than 2 m are
// "no echo"; off (the factory setting), every point is as measured.
#include <gtest/gtest.h>

#include "control_test_support.hpp"
#include "ldoem/control/near_field_filter.hpp"

namespace ldoem::control::test {
namespace {

// One profile after SET_FILTER `value` (sent in ROTATE, as S1 does), at 10 Hz, step 8.
protocol::Profile one_profile_with_filter(const char* set_filter) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(bench.head.duration);
  EXPECT_EQ(bench.reply_text(kTcp1, set_filter), "SET_FILTER reply 0001");
  const auto sent = bench.request(kTcp1, "TRANS_MEASURE");
  EXPECT_EQ(sent.size(), 1u);
  bench.request(kTcp1, "GET_PROFILE 0001 3dff");
  bench.advance_by(1s);
  const auto profiles = bench.profiles_to(kTcp1);
  EXPECT_EQ(profiles.size(), 1u);
  return profiles.empty() ? protocol::Profile{} : profiles.front();
}

TEST(NearFieldFilter, On_PointsNearerThanTwoMetresReportNoEchoOthersAsMeasured) {
  // The fake source measures 1 m + 1/256 m per tick of angle: the same points either way.
  const protocol::Profile off = one_profile_with_filter("SET_FILTER 0001 0000");
  const protocol::Profile on = one_profile_with_filter("SET_FILTER 0001 0001");
  ASSERT_EQ(on.sectors.size(), off.sectors.size());
  std::size_t suppressed = 0;
  std::size_t kept = 0;
  for (std::size_t s = 0; s < on.sectors.size(); ++s) {
    ASSERT_EQ(on.sectors[s].points.size(), off.sectors[s].points.size());
    for (std::size_t i = 0; i < on.sectors[s].points.size(); ++i) {
      const protocol::ProfilePoint& measured = off.sectors[s].points[i];
      const protocol::ProfilePoint& filtered = on.sectors[s].points[i];
      ASSERT_NE(measured.distance_q8_m, 0);  // the fake source always answers
      if (measured.distance_q8_m < kNearFieldLimit_q8) {
        EXPECT_EQ(filtered.distance_q8_m, 0) << i;
        EXPECT_EQ(filtered.echo, 0) << i;
        ++suppressed;
      } else {
        EXPECT_EQ(filtered, measured) << i;
        ++kept;
      }
    }
  }
  EXPECT_GT(suppressed, 0u);
  EXPECT_GT(kept, 0u);
}

TEST(NearFieldFilter, Suppress_LeavesNoEchoAndFarPointsAlone) {
  std::vector<BeamReturn> returns{{0, 0}, {100, 5}, {511, 7}, {512, 9}, {60000, 3}};
  EXPECT_EQ(suppress_near_field(returns), 2u);
  EXPECT_EQ(returns, (std::vector<BeamReturn>{{0, 0}, {0, 0}, {0, 0}, {512, 9}, {60000, 3}}));
}

}  // namespace
}  // namespace ldoem::control::test
