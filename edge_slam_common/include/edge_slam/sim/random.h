// Portable seeded pseudo-random numbers for the synthetic dataset. std:: distributions are
// implementation-defined, so everything here is computed bit-exactly from a 64-bit state
// (SplitMix64), making a seed produce byte-identical output on every platform.
#pragma once
#include <cstdint>

namespace edge_slam {

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}

  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [lo, hi] (inclusive); the tiny modulo bias is irrelevant here.
  int integer(int lo, int hi) {
    return lo + static_cast<int>(next() % static_cast<uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }
  // A child generator whose stream does not overlap this one's in practice.
  SplitMix64 fork() { return SplitMix64(next() ^ 0xD1B54A32D192ED03ull); }

 private:
  uint64_t state_;
};

// Stateless hash of a few integers to 64 bits, for per-pixel noise that must not depend on the
// order pixels are visited in.
inline uint64_t hash_mix(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
  SplitMix64 r(a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full ^
               (c + 0x165667B19E3779F9ull));
  return r.next();
}

}  // namespace edge_slam
