// One case (cases.hpp) through both casters, every answer judged against the oracle
// (judge.hpp), and the tallies scripts/numerics-report turns into docs/numerics.md's table.
#pragma once

#include "cases.hpp"
#include "judge.hpp"

#include "ldoem/raycast/ode_world.hpp"

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ldoem::oracle {

struct KindStats {
  std::uint64_t hits = 0;          // caster hits measured on a part of this kind
  double worst_error_m = 0.0;      // largest |range - exact|
  double worst_ulps = 0.0;         // largest error in ulps of the exact range
  double worst_ulps_steep = 0.0;   // the same over hits at incidence cos >= 0.5 (not grazing)
  double worst_ratio = 0.0;        // largest error / bound
  std::string worst_case;          // the inputs of the worst-ratio case
};

struct Stats {
  std::uint64_t cases = 0;
  std::uint64_t rays = 0;          // caster answers judged (each ray counts once per caster)
  std::uint64_t exact = 0;         // answers for which the filter could not decide
  std::uint64_t excused = 0;       // accepted within the bound of a boundary, tie or the reach
  std::uint64_t wrong_object = 0;
  std::uint64_t range_faults = 0;
  std::uint64_t missed = 0;
  std::uint64_t not_finite = 0;
  std::uint64_t oracle_failed = 0;
  std::array<KindStats, 6> kinds{};  // by Kind
  std::vector<std::string> faults;   // the first few, with their inputs
  std::uint64_t fault_cases = 0;     // cases with at least one fault
  // Faults by "caster kind" ("moving range"), every one counted.
  std::map<std::string, std::uint64_t> faults_by;
  // Every fault of this one run_case, uncapped (at most two per ray); merge() leaves them out,
  // the sweep writes them to its faults file (faults_file.hpp) case by case.
  std::vector<std::string> case_faults;  // "caster kind: what"

  std::uint64_t fault_count() const { return wrong_object + range_faults + missed + not_finite; }
  void merge(const Stats& other);
  // key=value lines, one per figure (scripts/numerics-report reads them back).
  std::string text() const;
};

// The oracle's parts of a world: primitives and planes as its ODE geoms hold them, meshes as the
// static caster's double world vertices (one part per triangle).
std::vector<Part> parts_of(const raycast::OdeWorld& world);

// Builds the scene's casters (EmbreeRayCaster; MovingRayCaster over its non-plane objects at
// fixed poses), casts every ray of the case with each and judges the answers. `describe` tags
// worst cases and faults with the case (hex of its bytes, for the sweep) when given.
void run_case(const OracleCase& c, Stats& stats, const std::string& describe = {});

}  // namespace ldoem::oracle
