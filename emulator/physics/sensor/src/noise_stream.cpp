#include <ldoem/sensor/noise_stream.hpp>

#include <cmath>
#include <numbers>

namespace ldoem::sensor {
namespace {

constexpr std::uint64_t kGoldenGamma = 0x9E3779B97F4A7C15ULL;  // 2^64 / phi, SplitMix64's increment
constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;

// Each key field is folded in through its own mix so that (rev 1, beam 2) and (rev 2, beam 1)
// land on unrelated hashes.
std::uint64_t hash_key(const NoiseKey& key) {
  std::uint64_t hash = mix64(key.seed + kGoldenGamma);
  hash = mix64(hash ^ (static_cast<std::uint64_t>(key.revolution) + 0x1000000000000001ULL));
  hash = mix64(hash ^ (static_cast<std::uint64_t>(key.beam_index) + 0x2000000000000003ULL));
  hash = mix64(hash ^ (static_cast<std::uint64_t>(key.sub_stream) + 0x3000000000000007ULL));
  return hash;
}

}  // namespace

std::uint64_t mix64(std::uint64_t value) {
  value = (value ^ (value >> 30)) * 0xBF58476D1CE4E5B9ULL;
  value = (value ^ (value >> 27)) * 0x94D049BB133111EBULL;
  return value ^ (value >> 31);
}

NoiseStream::NoiseStream(const NoiseKey& key) : key_hash_(hash_key(key)) {}

std::uint64_t NoiseStream::next_bits() {
  ++draws_;
  return mix64(key_hash_ + draws_ * kGoldenGamma);
}

double NoiseStream::uniform_open_closed() {
  // (k + 1) / 2^53 with k in [0, 2^53): the interval (0, 1].
  return static_cast<double>((next_bits() >> 11) + 1) * kTwoToMinus53;
}

double NoiseStream::standard_normal() {
  const double radius_uniform = uniform_open_closed();  // R1 in (0, 1] (D6): log never sees 0
  const double angle_uniform = uniform_open_closed();
  const double radius = std::sqrt(-2.0 * std::log(radius_uniform));
  return radius * std::cos(2.0 * std::numbers::pi * angle_uniform);
}

}  // namespace ldoem::sensor
