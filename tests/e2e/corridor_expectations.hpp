// What the paper's experiment must reproduce (docs/paper-reproduction.md), shared by the host and
// the vcan tests: the fitted cylinder and wall against the scene's true values.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "corridor_scan.hpp"

namespace ldoem::e2e {

// True values of scenes/corridor.yaml (docs/scenes.md).
inline constexpr double kTrueDiameterM = 0.195;
inline constexpr double kTrueLengthM = 0.998;
inline constexpr double kTrueWallDistanceM = 4.180;
// Acceptance tolerances. The wall's: ranges are quantised to 1/256 m (D6) and carry 1.5 mm noise,
// but thousands of wall points average that out to well under 5 mm.
inline constexpr double kDiameterToleranceM = 0.003;
inline constexpr double kLengthToleranceM = 0.02;
inline constexpr double kWallToleranceM = 0.005;
// 81 beams (20 deg at 0.25 deg) x 121 layers (21.6 deg at 0.18 deg); every beam hits something.
inline constexpr std::size_t kPaperPointCount = 81 * 121;

inline void expect_paper_fit(const CorridorFit& fit, const std::string& source) {
  EXPECT_NEAR(fit.cylinder_diameter_m, kTrueDiameterM, kDiameterToleranceM) << source;
  EXPECT_NEAR(fit.cylinder_length_m, kTrueLengthM, kLengthToleranceM) << source;
  EXPECT_NEAR(fit.wall_distance_m, kTrueWallDistanceM, kWallToleranceM) << source;
}

// The scan succeeded, our own fit of its PLY and ldoem-scan's printed fit both match the truth.
inline void expect_paper_scan(const ScanRun& run) {
  ASSERT_TRUE(run.started) << run.failure;
  ASSERT_EQ(run.exit_status, 0) << run.failure;
  std::string why;
  const auto own = fit_corridor_ply(run.ply_path, why);
  ASSERT_TRUE(own.has_value()) << why;
  EXPECT_EQ(own->point_count, kPaperPointCount);
  expect_paper_fit(*own, "fit of the PLY in the test");
  // For docs/paper-reproduction.md (ctest -V shows it).
  std::printf("fit of the PLY: %zu points, cylinder diameter %.2f mm, length %.4f m, wall %.4f m; scan %.1f s\n",
              own->point_count, own->cylinder_diameter_m * 1000.0, own->cylinder_length_m, own->wall_distance_m,
              run.wall_s);
  const auto printed = parse_tool_fit(run.scan_stdout);
  ASSERT_TRUE(printed.has_value()) << "no fit line in ldoem-scan's output: " << run.scan_stdout;
  expect_paper_fit(*printed, "ldoem-scan --fit");
}

// Byte-identical files, and on failure where the first difference is.
inline void expect_same_bytes(const ScanRun& a, const ScanRun& b, const std::string& what) {
  ASSERT_FALSE(a.ply_bytes.empty()) << what;
  ASSERT_EQ(a.ply_bytes.size(), b.ply_bytes.size()) << what;
  std::size_t first_difference = 0;
  while (first_difference < a.ply_bytes.size() && a.ply_bytes[first_difference] == b.ply_bytes[first_difference]) {
    ++first_difference;
  }
  EXPECT_EQ(first_difference, a.ply_bytes.size()) << what << ": first different byte at offset " << first_difference;
}

}  // namespace ldoem::e2e
