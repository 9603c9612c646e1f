#pragma once
// Counter-based random numbers: a deviate is a hash of (seed, particle id, stream), so it is the
// same on any rank count and after any restart, and nothing advances while a run steps (the
// seed is the whole random state). Jitter uses it now; flaw distributions will.
#include <cstdint>

namespace spall {

// Steele, Lea & Flood (2014), SplitMix64's output function.
inline std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// 64 random bits from (seed, id, stream).
inline std::uint64_t hashedBits(std::uint64_t seed, std::uint64_t id, std::uint64_t stream) {
  return splitmix64(splitmix64(seed * 0x9e3779b97f4a7c15ull + stream) ^ id);
}

// A uniform deviate in [-1, 1) from (seed, id, stream).
inline double hashedUniform(std::uint64_t seed, std::uint64_t id, std::uint64_t stream) {
  return 2.0 * static_cast<double>(hashedBits(seed, id, stream) >> 11) * 0x1.0p-53 - 1.0;
}

} // namespace spall
