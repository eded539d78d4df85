// The judge's tolerances (judge.hpp, docs/numerics.md "Error bounds") pinned on the cases that
// showed a term missing: each answer the derivation allows must pass, and one just beyond it
// must still be a fault, so that a tolerance is neither short of the arithmetic nor wider.
#include "differential.hpp"
#include "judge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace ldoem::oracle {
namespace {

// Doubles as hex literals: the case's inputs exactly.
Vec hex_vec(const char* x, const char* y, const char* z) {
  return {std::strtod(x, nullptr), std::strtod(y, nullptr), std::strtod(z, nullptr)};
}

Part triangle(std::uint32_t object, std::array<Vec, 3> vertices) {
  Part p;
  p.kind = Kind::triangle;
  p.object = object;
  p.vertices = vertices;
  return p;
}

PartScale moving_scale(const Part& p, const Vec& pose) {
  double size = 0.0;
  for (const Vec& v : p.vertices) size = std::max(size, std::hypot(v[0] - pose[0], v[1] - pose[1], v[2] - pose[2]));
  return {pose, size};
}

// Sweep seed 100, case 71401 (docs/numerics.md "Findings" 6): two copies of a 2e-6 m mesh
// whose poses, about 1.4e6 m from the origin, differ by one ulp in x (1.2e-10 m). The moving
// caster's float test sees the first copy's triangle unrounded, 3.8e-11 m farther along this
// ray than its double world vertices put it, beyond the second copy's double range (2.4e-11 m
// farther than the first's): the reach its query got. The order bound of a moving triangle
// holds that rounding (4 u (|pose| + S) / cos, 9.2e-10 m here); the float one alone (6.9e-12 m
// / cos) did not.
struct OneUlpApart {
  Vec pose_a = hex_vec("0x1.e84800000153cp+19", "-0x1.e848000003102p+19", "0x1.24f7fffffcadp+18");
  Vec pose_b = hex_vec("0x1.e84800000153dp+19", "-0x1.e848000003102p+19", "0x1.24f7fffffcadp+18");
  std::vector<Part> parts{
      triangle(0, {hex_vec("0x1.e8480000041bdp+19", "-0x1.e8480000008ebp+19", "0x1.24f7fffffa6b1p+18"),
                   hex_vec("0x1.e8480000036e4p+19", "-0x1.e8480000014e5p+19", "0x1.24f7fffffe628p+18"),
                   hex_vec("0x1.e847ffffff68ep+19", "-0x1.e848000002118p+19", "0x1.24f7ffffff455p+18")}),
      triangle(1, {hex_vec("0x1.e8480000041bep+19", "-0x1.e8480000008ebp+19", "0x1.24f7fffffa6b1p+18"),
                   hex_vec("0x1.e8480000036e5p+19", "-0x1.e8480000014e5p+19", "0x1.24f7fffffe628p+18"),
                   hex_vec("0x1.e847ffffff68fp+19", "-0x1.e848000002118p+19", "0x1.24f7ffffff455p+18")})};
  OracleRay ray{hex_vec("0x1.e8480000041e8p+19", "-0x1.e847fffffe53dp+19", "0x1.24f8000003484p+18"),
          hex_vec("-0x1.11aea84270349p-1", "-0x1.4c62aa583b11fp-1", "-0x1.150f3ac84fcd7p-1"),
          std::strtod("0x1.32dab344b5614p-13", nullptr)};
  // The moving caster's answer: the second copy, at its double range.
  CasterAnswer answer{true, 1, 2.3548928776394243e-06};

  std::vector<PartScale> scales() const { return {moving_scale(parts[0], pose_a), moving_scale(parts[1], pose_b)}; }
};

TEST(Judge, MovingMeshesOneUlpApart_TieWithinThePoseRounding) {
  const OneUlpApart c;
  const auto scales = c.scales();
  const Verdict v = judge(c.parts, scales, c.ray, UINT32_MAX, c.answer, Engine::moving);
  EXPECT_EQ(v.fault, Fault::none) << v.what;
  // The static caster rounds the double world triangle to float itself: no such term, and the
  // same answer from it is a fault (its scale: the float frame's centre, between the copies).
  std::vector<PartScale> frame(2, PartScale{c.pose_a, scales[0].size_m});
  EXPECT_EQ(judge(c.parts, frame, c.ray, UINT32_MAX, c.answer, Engine::embree).fault, Fault::wrong_object);
}

TEST(Judge, MovingMeshesOneUlpApart_NearerByMoreThanThePoseRoundingIsAFault) {
  OneUlpApart c;
  // The first copy 3e-9 m nearer along the ray (its range 3e-9 m less): beyond the 9.2e-10 m.
  for (Vec& v : c.parts[0].vertices) {
    for (int i = 0; i < 3; ++i) v[i] -= 3e-9 * c.ray.direction[i];
  }
  const Verdict v = judge(c.parts, c.scales(), c.ray, UINT32_MAX, c.answer, Engine::moving);
  EXPECT_EQ(v.fault, Fault::wrong_object) << v.what;
}

// The whole case as numerics_sweep --case replays it: both casters, every ray, no fault.
TEST(Judge, SweepSeed100Case71401_NoFault) {
  const std::string hex =
      "ca032cac5321bdae364281ea7795f03e95d77c61144310367e913d6ef475f349acad98d5213769aa2f3e80d3d7914ea36ad840de3fcc4d"
      "404e6bfac9a7bc43b97a52877cb84193356db06017926ef554ad4cb06341cafb835da486e21737c27f05e385eccdae9263828324a83a8f"
      "8f8f158a5e0bf27f915690f324595c9486fe92a42d792f1f0bfc4dac112befb4a153fc0253ebb9d91ed0ac5760462a83e03b51a6c788e8"
      "cfbcc977df7699087829cde98287863f063f758626285c696efeb930f18c222128232431e83ed38edfb4124ae94e9ea7fd12558d50647d"
      "6406e98ceab4b1455d274c99e8ff18dc09d28d30e1d8e1c10d8ce8f9f8e45ce2d8a2db982358155d32cd06bc5be5ab9c4fa80d58a5c694"
      "11164071d9e965938e31d1bfda2f35ccbaa84a164489a03f860e31b71a291032dd5f";
  std::vector<std::uint8_t> bytes;
  for (std::size_t k = 0; k + 1 < hex.size(); k += 2) {
    bytes.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(k, 2), nullptr, 16)));
  }
  Stats stats;
  run_case(make_case(bytes), stats);
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

// Sweep case 62c92895... (docs/numerics.md "Findings" 7, from the 1.3e8-answer run): a ray
// grazing one triangle of a far-posed mesh (cos 1.1e-6) and meeting another nearer. The moving
// caster answered the grazed one, 6.4 m too far: a fault of the caster, the judge unchanged.
TEST(Judge, SweepCase62c92895_NoFault) {
  const std::string hex =
      "62c92895c2d51f312e24db1dffc2840b121858b9e3918ddaf9f1c08b31bb85f51978896974100025f13625e807e321b14fc8f27c1364ca"
      "35877e5ee6968c5860b8dc4c91cc010ce8564b788ecdc5ee516b59c6e395cad560d1d612508811ba205bd43cf0a8285f51ecaa0740ae56"
      "683c9c476a5033c49850e9052281120e53580da2997a6f08cb13204e530f2b6e947189e4381c8eaa8b3970786a256605ab340fcf206d42"
      "76a6b8979e1ba1e1626df370c7aaa5b93abe9490c71c38aba225827193a9c846c752863a1a87161167325f4691842fe8e44c13deae4305"
      "dd2847901e4e7e654b06dc23f69275fb6624ec57cb1224ee10294715fa7e22027c377413a9558b2e55bd18eac0f63b20684f6ae38a8880"
      "217216597357df341f8b55334b3037ce46d9b99d8a64a926ab8e255d371a9dfab3cddd6b3fcdd385b29dc24f93f684161d2d5dba58a6af"
      "acf75056f36862c8f7048bd3276910dc516f006526317d8876149dbfc110097c3a37c3f950b8ef7ec6dadd83fe28a92b2e126dd6589105"
      "292a0c7a51404020866144a9ceaa1b";
  std::vector<std::uint8_t> bytes;
  for (std::size_t k = 0; k + 1 < hex.size(); k += 2) {
    bytes.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(k, 2), nullptr, 16)));
  }
  Stats stats;
  run_case(make_case(bytes), stats);
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

// A --far-meshes sweep case (docs/numerics.md "Findings" 8): a ray from a far-posed sliver,
// grazing its plane. The moving caster's plain cross product put the exact crossing behind the
// origin 1.08e-4 m ahead of it; a fault of the caster, the judge unchanged.
TEST(Judge, SweepCase269cc5b4_NoFault) {
  const std::string hex =
      "269cc5b4c3fcd54a3576186b976ede943ee22fac2ea9adcf6cfb4ed68e03f8e6c3811a5e1a01d9c40406509822609d21fb00c9c7b32dc2"
      "285a70cb4c5865aa23e2b73272a00a6e77b27079a991b16c03c1cb9c4ecaac93a51b44fb3155746446f3db7fb9e4f3b9ab0687f0930d9d"
      "4b5142a71aac99392b3dfabd78c7eccf21b47e8eae514e6d25df31d8293d335cd432e6ab69925aa3f5a99bcb537ead13ddb59c0a56748e"
      "6d0bd06c878ba5d5b52b7d86d91bd77a7d61d554388ee07839e11f3a9a0580d3c3c31e81f6a85e6f11d9094c548279121aae58b8ce7e71"
      "aa041ab021a319bf082748cd0652144928547c3b75a1da0fe24fcd40d29ea030887f3b4649a22aaa16514e721ba712f05d45f4cd0e0461"
      "2899a315ce1f16507feb42cca8729b62071e038dfc07a03ebffdca6f3162e477a5de4ec2ba8bf1f28cfef0f8f4a4d89767200300ea521d"
      "9d7e801fe0a8bbd404e234219a85b1403642fc27950e450faec20eebdf385342bf0edcda5c6ece2dff62687c6aa18aa659c8e9bdb47034"
      "aa7f813f4d6cd7e93e71647ba2c8522f44d809f243790e1631ad8e0c7bc4db2d29f99e8aec39d284cf4eed431caee505abaed3f6331651"
      "b2790402811f45f192e289452446fef6227cdb";
  std::vector<std::uint8_t> bytes;
  for (std::size_t k = 0; k + 1 < hex.size(); k += 2) {
    bytes.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(k, 2), nullptr, 16)));
  }
  Stats stats;
  run_case(make_case(bytes), stats);
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

}  // namespace
}  // namespace ldoem::oracle
