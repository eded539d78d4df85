#include <gtest/gtest.h>

#include "cases.hpp"
#include "options.hpp"
#include "vector_table.hpp"

namespace ldoem::conformance {
namespace {

TEST(Glob, EmptyFilterList_MatchesEverything) { EXPECT_TRUE(matches_any({}, "tcp/vectors/GET_STATUS")); }

TEST(Glob, StarSpansSlashes) {
  EXPECT_TRUE(matches_any({"*/states/*"}, "tcp/states/TRANS_IDLE_in_MEASURE"));
  EXPECT_TRUE(matches_any({"tcp/*"}, "tcp/vectors/GET_STATUS"));
  EXPECT_FALSE(matches_any({"can/*"}, "tcp/vectors/GET_STATUS"));
  EXPECT_TRUE(matches_any({"can/*", "*GET_STATUS"}, "tcp/vectors/GET_STATUS"));
}

TEST(Slug, SpecNames_BecomeShellFriendly) {
  EXPECT_EQ(slug("SET_CONFIG global id 1, 10 Hz, 0.5°"), "SET_CONFIG_global_id_1_10_Hz_0.5deg");
  EXPECT_EQ(slug("SET_TIME_REL −10 ms"), "SET_TIME_REL_-10_ms");
  EXPECT_EQ(slug("GET_PROFILE 1 × 0x39FF"), "GET_PROFILE_1_x_0x39FF");
  EXPECT_EQ(slug("TRANS_IDLE → IDLE"), "TRANS_IDLE_to_IDLE");
  EXPECT_EQ(slug("TRANS_ROTATE 10 Hz (layout per S1, non-zero value per S2's semantics)"),
            "TRANS_ROTATE_10_Hz_layout_per_S1_non-zero_value_per_S2_s_semantics");
}

TEST(Cases, NamesAreUniqueAndEveryRequestVectorHasAnExpectation) {
  auto vectors = load_vector_table(embedded_vectors_yaml());
  ASSERT_TRUE(vectors) << vectors.error();
  const std::vector<Case> cases = all_cases(*vectors);
  std::set<std::string> names;
  for (const Case& c : cases) EXPECT_TRUE(names.insert(c.name).second) << "duplicate " << c.name;
  EXPECT_EQ(cases.front().name, "power-up/D4_defaults");  // must run before anything configures
  EXPECT_GT(cases.size(), 80u);
}

TEST(Cases, DeviceTarget_DropsEmulatorOnlyCases) {
  auto vectors = load_vector_table(embedded_vectors_yaml());
  ASSERT_TRUE(vectors);
  std::size_t emulator = 0;
  std::size_t device = 0;
  for (const Case& c : all_cases(*vectors)) {
    emulator += c.applies_to(protocol::Transport::tcp, Target::emulator);
    device += c.applies_to(protocol::Transport::tcp, Target::device);
  }
  EXPECT_LT(device, emulator);
  EXPECT_GT(device, 40u);
}

}  // namespace
}  // namespace ldoem::conformance
