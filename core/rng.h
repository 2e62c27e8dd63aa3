#pragma once
#include <cstdint>
#include <random>

namespace flsd {

// A deterministic seed for stream `index` of a run seeded with `seed` (SplitMix64 mixing), so that
// each environment draws from its own stream whatever the thread count.
inline uint64_t StreamSeed(uint64_t seed, uint64_t index) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

using Rng = std::mt19937_64;

inline double Uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

}  // namespace flsd
