// The judge's tolerances (judge.hpp, docs/numerics.md "Error bounds") pinned on the cases that
// showed a term missing: each answer the derivation allows must pass, and one just beyond it
// must still be a fault, so that a tolerance is neither short of the arithmetic nor wider.
#include "differential.hpp"
#include "judge.hpp"

#include "ldoem/raycast/embree_ray_caster.hpp"

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
  // The static caster rounds the double world triangle to float itself: no such term (its
  // scale: the float frame's centre, between the copies). Its order bound, 1.7e-11 m with
  // Embree's float normal (docs/numerics.md "Findings" 11), is a twentieth of the moving one:
  // with the first copy 1e-10 m nearer, the same answer is a fault from it, not from the
  // moving caster.
  std::vector<PartScale> frame(2, PartScale{c.pose_a, scales[0].size_m});
  EXPECT_EQ(pose_rounding(c.parts[0], frame[0], c.ray, c.answer.range_m, Engine::embree), 0.0);
  EXPECT_LT(20.0 * order_bound(c.parts[0], frame[0], c.ray, c.answer.range_m, Engine::embree),
            order_bound(c.parts[0], scales[0], c.ray, c.answer.range_m, Engine::moving));
  OneUlpApart nearer;
  for (Vec& v : nearer.parts[0].vertices) {
    for (int i = 0; i < 3; ++i) v[i] -= 1e-10 * nearer.ray.direction[i];
  }
  EXPECT_EQ(judge(nearer.parts, nearer.scales(), nearer.ray, UINT32_MAX, nearer.answer, Engine::moving).fault, Fault::none);
  EXPECT_EQ(judge(nearer.parts, frame, nearer.ray, UINT32_MAX, nearer.answer, Engine::embree).fault, Fault::wrong_object);
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

// A sweep case from the hex of its bytes, as numerics_sweep --case reads it.
OracleCase case_of(const std::string& hex) {
  std::vector<std::uint8_t> bytes;
  for (std::size_t k = 0; k + 1 < hex.size(); k += 2) {
    bytes.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(k, 2), nullptr, 16)));
  }
  return make_case(bytes);
}

// The whole case as numerics_sweep --case replays it: both casters, every ray, judged.
Stats replay(const std::string& hex) {
  Stats stats;
  run_case(case_of(hex), stats);
  return stats;
}

TEST(Judge, SweepSeed100Case71401_NoFault) {
  const Stats stats = replay(
      "ca032cac5321bdae364281ea7795f03e95d77c61144310367e913d6ef475f349acad98d5213769aa2f3e80d3d7914ea36ad840de3fcc4d"
      "404e6bfac9a7bc43b97a52877cb84193356db06017926ef554ad4cb06341cafb835da486e21737c27f05e385eccdae9263828324a83a8f"
      "8f8f158a5e0bf27f915690f324595c9486fe92a42d792f1f0bfc4dac112befb4a153fc0253ebb9d91ed0ac5760462a83e03b51a6c788e8"
      "cfbcc977df7699087829cde98287863f063f758626285c696efeb930f18c222128232431e83ed38edfb4124ae94e9ea7fd12558d50647d"
      "6406e98ceab4b1455d274c99e8ff18dc09d28d30e1d8e1c10d8ce8f9f8e45ce2d8a2db982358155d32cd06bc5be5ab9c4fa80d58a5c694"
      "11164071d9e965938e31d1bfda2f35ccbaa84a164489a03f860e31b71a291032dd5f");
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

// docs/numerics.md "Findings" 9. A ray lying in a plane to within rounding (its origin 1.2e-12 m
// off it, its direction 6.2e-18 from parallel, pointing away): the static caster's n . d came
// out -2^-54 and its height -2^-38, a hit at exactly 2^16 m where the exact plane is behind.
// Whether a plane that parallel is hit is not decided by the arithmetic.
TEST(Judge, RayInAPlaneWithinRounding_AnyRangeOrMiss) {
  const Stats stats = replay(
      "20f149ead3e8aa8296b299bc48143643dddec166542891bcc41f2a32fb06aa91200dc77774ffe67d9455ef02d6f7f896572a9fa1e058a0"
      "a2c82b3f5879c6284f5752f8d567e4844e1af77b04f641a0ae11731928f5f815a1198f727d24cbf594d1db8ccae66b4a1378e43f87a957"
      "eeecbb67499f93809a62b0220064ca7d21f98d349a0ae753a04f749d270868c3f9c176eb9ee19a2a8d3b1ba6220d7c2a868841b67ef960"
      "7dc9c958bb4d79c8cf33d40fc6901cdbd1f6e575b6da1e31d7303f457a9cafce6f9320ca93c0f9d145e3f53c672dfe9bc3cf9ae84ab86b"
      "fa8556b447a72a3d8941038fbc9076fba1e293abd455dbc3d930121c5cf1ac865a3b0efa01372cb706947b4381fab75ad44a04b4");
  EXPECT_EQ(stats.rays, 35u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

TEST(Judge, PlaneBehindAtAGrazingAngle_HitIsAFault) {
  Part plane;
  plane.kind = Kind::plane;
  plane.normal = {0, 0, 1};
  plane.offset = 0.0;
  // 1 m above the plane, climbing at 1e-13 rad (1000 times the parallel tolerance): no hit.
  const OracleRay ray{{0, 0, 1}, {1, 0, 1e-13}, 1e9};
  const std::vector<Part> parts{plane};
  const std::vector<PartScale> scales(1);
  EXPECT_EQ(judge(parts, scales, ray, UINT32_MAX, CasterAnswer{true, 0, 65536.0}, Engine::embree).fault, Fault::wrong_object);
  // Parallel within the tolerance (1e-16 rad), 1e-12 m above: a miss or a hit anywhere the
  // rounded quotient reaches (1e-12 m / 16 u is 56 m or more).
  const OracleRay parallel{{0, 0, 1e-12}, {1, 0, 1e-16}, 1e9};
  EXPECT_EQ(judge(parts, scales, parallel, UINT32_MAX, CasterAnswer{true, 0, 65536.0}, Engine::embree).fault, Fault::none);
  EXPECT_EQ(judge(parts, scales, parallel, UINT32_MAX, CasterAnswer{}, Engine::embree).fault, Fault::none);
  EXPECT_EQ(judge(parts, scales, parallel, UINT32_MAX, CasterAnswer{true, 0, 1.0}, Engine::embree).fault, Fault::wrong_object);
  // 1 m above and parallel within the tolerance: no rounding of n . d brings the plane within
  // 2.8e14 m, so a hit at 65536 m is a fault.
  const OracleRay high{{0, 0, 1}, {1, 0, 1e-16}, 1e9};
  EXPECT_EQ(judge(parts, scales, high, UINT32_MAX, CasterAnswer{true, 0, 65536.0}, Engine::embree).fault, Fault::wrong_object);
  EXPECT_EQ(judge(parts, scales, high, UINT32_MAX, CasterAnswer{}, Engine::embree).fault, Fault::none);
}

// "Findings" 10: a ray through a fold of a 4e-6 m mesh 1e6 m out, its triangle at 3.18251e-6 m,
// a sliver behind it at 3.18253e-6 m whose float distance (normal lost to cancellation) was
// 1.1e-10 m short; Embree kept the least float distance, the sliver. The caster now orders
// triangles by their double ranges.
TEST(Judge, SweepSliverBehindATriangle_NoFault) {
  const std::string hex =
      "1a06a0e6e2903d58ab9f14ffc2758180690230afdbba2ba6c401149360f4383f906c2e9591d38b726bb82f18dee08f03b5e2ee0a909ec5"
      "063b7648c728c33c20eb70d68a15f5f19b2f7348acaff7bac33b00ab854ae9342b20a94b3f12e16dd32ae87aa07178c54f5b86cdb8fcb2"
      "a0208a2da65242a183e31a491fadb767ee25b460d39ea8b48ac368c2e521c498c3cd19e18cabafa611068b080949c8d587eb311d97d01a"
      "04bf1efa1455b468474c85fbca1ccac52a87b0c380aec02ab5a7efb8c4459fcf2eeb6eddb554e452686f34dbb86c079e2bb56faac4e1c9"
      "7e8ead4ed46f06203f9f53bf98c4bb4dcb0bfa7d2801efc3e81065fb7c7874da77974e27231856262ec55a52c038eec71e40bcf01c3009"
      "c416b45f443fb472ca5337b1cbebdf6bd4763a3c701869ccdac93b340cbb78a08634b6c58600531b933159f1a3e0937b97e399fdaa847d"
      "a9aa888f81276b06954662df5ee252fd1e3c35c43040ed84df7e7a2f4af66a7e8e02acc719f2a52025f9a72f2b666b";
  const Stats stats = replay(hex);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
  // Within the judge's bounds a swap is allowed (each triangle's float distance may err); the
  // caster now gives the nearer triangle at its double range.
  const OracleCase c = case_of(hex);
  const raycast::OdeWorld world(c.scene);
  const raycast::EmbreeRayCaster caster(world);
  const auto hit = caster.cast(c.rays.at(0));
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->object_index, 1u);
  EXPECT_NEAR(hit->range_m, 3.1825108892170759e-06, 1e-18);
}

// The same fault 1e6 m out at 2.7e5 m: the caster answered a triangle of the mesh 70 m behind
// the nearest (its bound 0.86 m).
TEST(Judge, SweepTriangleSeventyMetresBehind_NoFault) {
  const Stats stats = replay(
      "76def109c674414a25a247548df96e5d70a606bc1dcb989bd21158c2e0306c15eb5a42d4f818648fa71d5841533f96f86baad14fb7c23a"
      "6cb9c0b7783e1c6bd404b7bb4f8f4137b764335c955e0c756e42aef847709c005f1a0ee841c0e39bd4116c3013105856cf872ebedd9598"
      "4455f1a86c26771de86b24297c02dad085df57283fbd44dad48724227df9e7e9637a239025f16e4183db54524ca538f2e8727d2b7394cf"
      "233effb752a8f86e692db3a191dbf361fb6223ac288b809adb993d4bf0eb49a0414a9dcd9a16f50eeb371bf818d7a67f17f41da6a3fb45"
      "e573ef4642001fb5bfe6975494fb5c66ae29b30a5d4d8ac265586415231d3ff3e82cd50a52188041838d3b1aaceeba933ab3400854f5df"
      "a613f06ac5934f9deccb4d432e9244ba7b569458088b540583e4f15a5d1dc3f72c3e38a6e150f3eb22404b49f81025d3a147b713e2e142"
      "c27db436455eec384d7f23ecde54429fa7d7e03a2fc86ca8812f8a7035cccd80769ed6ad8c9c238cac9dfb3c711ff2ca0c27dbb3815289"
      "ef");
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

// "Findings" 11: a ray starting 2.7e-11 m before a sliver (twice its area 3.2e-16 m^2, edges
// 5e-6 m) of a mesh 1e6 m out. Embree's float distance of the sliver errs by ~8e-10 m (its
// normal, a cross product of edges, lost to cancellation), so it fell below tnear = 0 and the
// caster answered a plane at 4.5e-6 m. The order bound of a triangle carries the sliver factor.
struct SliverAtTheOrigin {
  std::vector<Part> parts{
      [] {
        Part p;
        p.kind = Kind::plane;
        p.object = 0;
        p.normal = hex_vec("0x1.ab7c14b0ffc6bp-2", "0x1.8651b2b934a4p-1", "-0x1.fa65550e9a66cp-2");
        p.offset = std::strtod("-0x1.e1acac4b7201cp+18", nullptr);
        return p;
      }(),
      triangle(1, {hex_vec("0x1.e847fffffe319p+19", "-0x1.e848000000d0ap+19", "0x1.24f8000014cd8p+18"),
                   hex_vec("0x1.e848000002e7dp+19", "-0x1.e847fffffd5fep+19", "0x1.24f800000de5p+18"),
                   hex_vec("0x1.e8480000079e1p+19", "-0x1.e847fffff9ef1p+19", "0x1.24f8000006fc8p+18")})};
  // The static caster's float frame: the middle of the mesh's bounds.
  Vec frame{0.5 * (std::strtod("0x1.e847fffffe319p+19", nullptr) + std::strtod("0x1.e8480000079e1p+19", nullptr)),
            0.5 * (std::strtod("-0x1.e848000000d0ap+19", nullptr) + std::strtod("-0x1.e847fffff8922p+19", nullptr)),
            0.5 * (std::strtod("0x1.24f8000006fc8p+18", nullptr) + std::strtod("0x1.24f8000014cd8p+18", nullptr))};
  OracleRay ray{hex_vec("0x1.e8480000018d2p+19", "-0x1.e847fffffe5dp+19", "0x1.24f800000fe15p+18"), {0, 0, -1},
                std::strtod("0x1.0557c9f390078p-11", nullptr)};
  CasterAnswer answer{true, 0, 4.5217039754886592e-06};  // the plane

  std::vector<PartScale> scales() const { return {PartScale{}, moving_scale(parts[1], frame)}; }
};

TEST(Judge, SliverAtTheOrigin_LostWithinItsFloatDistance) {
  const SliverAtTheOrigin c;
  // 5e-7 m: far beyond the plain float bound (5e-12 m), the sliver's normal rounding.
  EXPECT_GT(float_normal_error(c.parts[1], c.ray, 2.7e-11), 1e-7);
  const Verdict v = judge(c.parts, c.scales(), c.ray, UINT32_MAX, c.answer, Engine::embree);
  EXPECT_EQ(v.fault, Fault::none) << v.what;
}

TEST(Judge, SliverAtTheOrigin_FartherThanItsFloatDistanceIsAFault) {
  SliverAtTheOrigin c;
  // The origin 2e-6 m back along the ray: the sliver at 2e-6 m, its order bound 5e-7 m, the
  // plane 4.5e-6 m beyond it (and the ray still farther from the sliver's edges, 1.7e-11 m,
  // than its boundary tolerance).
  for (int i = 0; i < 3; ++i) c.ray.origin[i] -= 2e-6 * c.ray.direction[i];
  c.ray.reach += 2e-6;
  c.answer.range_m += 2e-6;
  const auto scales = c.scales();
  ASSERT_LT(order_bound(c.parts[1], scales[1], c.ray, 2e-6, Engine::embree), 1e-6);
  const Verdict v = judge(c.parts, scales, c.ray, UINT32_MAX, c.answer, Engine::embree);
  EXPECT_EQ(v.fault, Fault::wrong_object) << v.what;
}

TEST(Judge, SweepSliverAtTheOrigin_NoFault) {
  const Stats stats = replay(
      "1a0b0f5d367e1ce85290ff0b535d5463c6fd66643126e1e28f082e3788e99601a371af679ea08140762096b2779b218a2051fb8b21c6f0"
      "4028a6d8b85db83efe2007c155799f71562b23e0cd5463e153d81e48c9f3b896395466ae5c4af4ec9a3328d5b4e1009f656d64c9ae9903"
      "d7c0fcdaaae1c1dc29d27cf4355d3ac1b71d1cee0ef538b964020f9fd5ba3b9414f2d52f182731a5ca57313f1d5b353661bdb76afaf5ca"
      "fe41dc80eb49d0caf75d740842352b5616fabc490e0d380da3dd9a20497933f74caad3191fb5b661e06c37c060c7f1c5da7f6505c9669e"
      "07b9fa951e9a528484002fd9b8fd56a2e5bd353eac8afa108ad7f34c2caae57775cfea14f55171dd39f674d23c21020958e817dad98b65"
      "03aa7de56cd00ca14370232b98b4dc2948b4ee400cb52da5bb7a4c9e1abe46e52f2bbd9f59675952d9ef69da6c9d4d43f00f52c37b2607"
      "5d9f570e40fb52b41dcd722ca36450af4d920b04bcba8ecc6f061f1a7fceeefee2ced04687a3abbc27a90223");
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
  const Stats stats = replay(hex);
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
  const Stats stats = replay(hex);
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

// A --far-meshes sweep case (docs/numerics.md "Findings" 12): the static caster's plain cross
// product of a far sliver (L^2 / 2A = 4.3e6) put a grazing ray's crossing 3.0e-4 m ahead, the
// exact one being 4.0e-5 m behind the origin; a fault of the caster, the judge unchanged.
TEST(Judge, SweepCase069f2bab_NoFault) {
  const std::string hex =
      "069f2bab18fa0f95f59e8460e8426f272d465bac8c96f099ab2ebc8f4a0c6ff6d3d25d3445080faca3e6cdc51e9b0f37ad50a73c99473b"
      "7f7ad3cd9b90bbcb1806506e26ac2b4e6c6d0946d982cda19016462b0a56def8fb7552cdaecb43b00f19c28025efbb149ce5e71c604381"
      "a13d801ae56eacc34ca58a8b4cafebb02b6c1f6f42740f42f991f5dd7db669db1183";
  const Stats stats = replay(hex);
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

// "Findings" 13 (the 1.1e8-answer run): a ray clipping the rim of a cylinder (radius 0.094 m)
// posed 1e6 m out: it enters through the cap at cos 4.6e-4 and leaves through the side 2.8e-11
// m later. The moving caster's range was 1.67e-12 m short, within the cap's bound (1.2e-10 m);
// the judge took the side's cosine (~1, bound 5.6e-14 m), having placed the hit point in world
// coordinates, rounded by ~1e-10 m at 1e6 m, nearer the side than the cap.
const char* const kCylinderRimFarOut =
      "6272d72a363d785d004da963dc9720546a3f1fc42b7607d12b0daea091ca969f04cb68782179f634bf6ead494638f830a98cbff0796240"
      "4cef4edbe523087f794bf852a78031d6cac781202ff86bbdcec313ab8703d13b62eabbb4adf021945c01008882f3859bfac6b44eb4a3ad"
      "d17f05e3db11a24b6cc0acf977ff7915f75361832c68b4efc10c9f1e70d77d50b6cfe24cfe72ed741e82d4816f10055bd0abe4f8c22c94"
      "7b7b927cab64124ed7e50fa1eaecdaf55b2ff6d0d207894e06fc679b2d51ed8f4cb5b44d151fda2b73ec0ed172c1af3fc2ea7b892f5367"
      "0a1b054c160001f5a1103bd2b724ae238f5a10e9ff565644e344af0339b5c0117b23b06f196854c1a8519d0bb3dba988c0a5594694c98a"
      "05b70208f5e0ae477a04fd6b8b0daa4ad9250d33c8d9f42c151f5e3279931be109a775afa6e50c2112d16793edb793208af3be0f68f6b6"
      "799b6a37e3ce8ec316df81eb2496c215f814374e483937fc83b226ddb95409e1a4ad2b627ef39767aca33bb4d2b43755922dc50788c0e2"
      "7b15312cacd3bee3892fb52365bac189a3cd8435b5d31975a72bfbf663721d0d4212b9f92bcaf6ecac1f5ccb44ba5fbf8d0e6bb39c6b2b"
      "891e4f1673d3607850f0c5a69eb5bb793bafaf591e6414a663727611486748060a03b44e516d5cb8232426629b721741322aa7330787ca"
      "8ff9a6723c";

TEST(Judge, SweepCylinderRimFarOut_NoFault) {
  const Stats stats = replay(kCylinderRimFarOut);
  EXPECT_GT(stats.rays, 0u);
  EXPECT_EQ(stats.fault_count(), 0u) << (stats.faults.empty() ? std::string() : stats.faults.front());
}

TEST(Judge, CylinderRimFarOut_OffByMoreThanTheCapBoundIsAFault) {
  const OracleCase c = case_of(kCylinderRimFarOut);
  const raycast::OdeWorld world(c.scene);
  const std::vector<Part> all = parts_of(world);
  const auto ray = std::find_if(c.rays.begin(), c.rays.end(), [](const raycast::Ray& r) {
    return r.origin_m.x() == 999999.62393206684 && r.direction.x() == 0.12674060591874234;
  });
  ASSERT_NE(ray, c.rays.end());
  const OracleRay r{{ray->origin_m.x(), ray->origin_m.y(), ray->origin_m.z()},
                    {ray->direction.x(), ray->direction.y(), ray->direction.z()}, std::min(ray->max_range_m, 1e9)};
  // The cylinder alone (object 2), with the moving caster's scale: its centre, radius + half length.
  std::vector<Part> parts;
  for (const Part& p : all) {
    if (p.object == 2) parts.push_back(p);
  }
  ASSERT_EQ(parts.size(), 1u);
  ASSERT_EQ(parts[0].kind, Kind::cylinder);
  const std::vector<PartScale> scales{PartScale{parts[0].centre, parts[0].radius + parts[0].half_length}};
  const double exact = 3.8593504267937164;
  // The cap's bound, 64 u (P + S + t) / cos with cos 4.6e-4: 1.2e-10 m.
  const double bound = range_bound(parts[0], scales[0], r, exact, Engine::moving);
  EXPECT_GT(bound, 1e-10);
  EXPECT_LT(bound, 1.5e-10);
  EXPECT_EQ(judge(parts, scales, r, UINT32_MAX, CasterAnswer{true, 2, 3.8593504267920484}, Engine::moving).fault, Fault::none);
  // 1e-9 m short (eight times the bound, and the rim 2.8e-11 m away does not excuse it).
  const Verdict v = judge(parts, scales, r, UINT32_MAX, CasterAnswer{true, 2, exact - 1e-9}, Engine::moving);
  EXPECT_EQ(v.fault, Fault::range) << v.what;
}

}  // namespace
}  // namespace ldoem::oracle
