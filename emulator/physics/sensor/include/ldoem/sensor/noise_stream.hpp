// D6 counter-based random numbers: the n-th number of a beam is a pure function of
// (seed, revolution, beam index, sub-stream, n), so results never depend on thread scheduling,
// on the order beams are processed, or on what else drew numbers. There is no global generator.
#pragma once

#include <cstdint>

namespace ldoem::sensor {

struct NoiseKey {
  std::uint64_t seed = 0;
  std::uint32_t revolution = 0;
  std::uint32_t beam_index = 0;
  std::uint32_t sub_stream = 0;  // e.g. a sub-ray; 0 for the beam's own range noise
};

// One short-lived stream per (key). Construction draws nothing; draws() counts the 64-bit words
// taken so far, so tests can prove that a scene without noise draws no numbers.
class NoiseStream {
 public:
  explicit NoiseStream(const NoiseKey& key);

  // The next 64 uniformly distributed bits: SplitMix64's output function applied to
  // key_hash + (n + 1) * golden gamma, i.e. a counter-based generator.
  [[nodiscard]] std::uint64_t next_bits();

  // Uniform in (0, 1] with 53-bit resolution: never 0, so log() in Box-Muller stays finite.
  [[nodiscard]] double uniform_open_closed();

  // Standard normal by Box-Muller (cosine branch; two words per value).
  [[nodiscard]] double standard_normal();

  [[nodiscard]] std::uint64_t draws() const { return draws_; }

 private:
  std::uint64_t key_hash_;
  std::uint64_t draws_ = 0;
};

// SplitMix64's finaliser (Steele, Lea, Flood 2014): a bijective 64-bit mix.
[[nodiscard]] std::uint64_t mix64(std::uint64_t value);

}  // namespace ldoem::sensor
