#pragma once
// 64-bit space-filling-curve keys over a box: Morton (Z-order) and Hilbert, in 1, 2 and 3
// dimensions. Physics-free. Keys use 63 bits in 1D, 2 x 31 in 2D and 3 x 21 in 3D, so every key
// is below kKeyEnd and UINT64 arithmetic on key ranges never overflows.
//
// Hilbert: J. Skilling, "Programming the Hilbert curve", AIP Conf. Proc. 707, 381 (2004): the
// coordinates are turned into the "transposed" Hilbert index in place, whose bits, interleaved
// from the most significant down, are the index.
#include "spall/core/Types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace spall::parallel {

enum class Curve { Hilbert, Morton };

inline constexpr std::uint64_t kKeyEnd = std::uint64_t{1} << 63;

template <int Dim> constexpr int keyBits() {
  return Dim == 1 ? 63 : Dim == 2 ? 31 : 21;
}

// Morton key of integer coordinates with `bits` bits each: bit b of axis d goes to b*Dim + d.
template <int Dim>
std::uint64_t mortonKey(const std::array<std::uint64_t, Dim>& c, int bits = keyBits<Dim>()) {
  if constexpr (Dim == 1) return c[0];
  std::uint64_t key = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (int d = Dim - 1; d >= 0; --d)
      key = (key << 1) | ((c[static_cast<std::size_t>(d)] >> b) & 1u);
  return key;
}

// Spreads the low bits of v so that bit b lands on bit b * Dim (the rest zero): Dim = 2 takes
// 32 bits, Dim = 3 takes 21.
template <int Dim> constexpr std::uint64_t spreadBits(std::uint64_t v) {
  if constexpr (Dim == 2) {
    v &= 0xffffffffu;
    v = (v | (v << 16)) & 0x0000ffff0000ffffull;
    v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
    v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
  } else if constexpr (Dim == 3) {
    v &= 0x1fffffu;
    v = (v | (v << 32)) & 0x001f00000000ffffull;
    v = (v | (v << 16)) & 0x001f0000ff0000ffull;
    v = (v | (v << 8)) & 0x100f00f00f00f00full;
    v = (v | (v << 4)) & 0x10c30c30c30c30c3ull;
    v = (v | (v << 2)) & 0x1249249249249249ull;
  }
  return v;
}

// Hilbert key of integer coordinates with `bits` bits each (Skilling 2004, AxesToTranspose).
// Branch-free: the invert/exchange choice depends on the coordinates' bits, which a branch
// mispredicts half the time (the keys of every particle are taken every step for migration).
template <int Dim>
std::uint64_t hilbertKey(std::array<std::uint64_t, Dim> X, int bits = keyBits<Dim>()) {
  if constexpr (Dim == 1) return X[0];
  const std::uint64_t M = std::uint64_t{1} << (bits - 1);
  // Inverse undo of the excess work: where bit Q of X[i] is set, invert the low bits of X[0];
  // otherwise exchange them with X[i]'s.
  for (std::uint64_t Q = M; Q > 1; Q >>= 1) {
    const std::uint64_t P = Q - 1;
    for (int i = 0; i < Dim; ++i) {
      const std::uint64_t set =
          std::uint64_t{0} - static_cast<std::uint64_t>((X[static_cast<std::size_t>(i)] & Q) != 0);
      const std::uint64_t t = (X[0] ^ X[static_cast<std::size_t>(i)]) & P & ~set;
      X[0] ^= (P & set) | t;
      X[static_cast<std::size_t>(i)] ^= t;
    }
  }
  // Gray encode.
  for (int i = 1; i < Dim; ++i)
    X[static_cast<std::size_t>(i)] ^= X[static_cast<std::size_t>(i - 1)];
  std::uint64_t t = 0;
  for (std::uint64_t Q = M; Q > 1; Q >>= 1)
    if (X[Dim - 1] & Q) t ^= Q - 1;
  for (int i = 0; i < Dim; ++i) X[static_cast<std::size_t>(i)] ^= t;
  // Interleave, axis 0 most significant within each level: bit b of axis i goes to
  // b * Dim + (Dim - 1 - i).
  const std::uint64_t low = bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
  std::uint64_t key = 0;
  for (int i = 0; i < Dim; ++i)
    key |= spreadBits<Dim>(X[static_cast<std::size_t>(i)] & low) << (Dim - 1 - i);
  return key;
}

// Keys of positions inside a fixed cube (the box's largest extent from its low corner); positions
// outside are clamped to its faces, so a particle that flew out of the box still gets a valid key
// (the box is refreshed at each rebalance).
template <int Dim> class KeyMap {
public:
  KeyMap() = default;
  KeyMap(const Vec<Dim>& lo, const Vec<Dim>& hi, Curve curve) : lo_(lo), hi_(hi), curve_(curve) {
    // One scale for all axes (the largest extent): cubic cells keep the curve's locality the
    // same in every direction, and a long thin body is cut across its length.
    const double cells = std::ldexp(1.0, keyBits<Dim>()); // 2^bits
    double span = 0.0;
    for (int d = 0; d < Dim; ++d) span = std::max(span, hi[d] - lo[d]);
    scale_ = Vec<Dim>::Constant(span > 0.0 ? cells / span : 0.0);
  }
  std::uint64_t operator()(const Vec<Dim>& x) const {
    constexpr std::uint64_t maxCoord = (std::uint64_t{1} << keyBits<Dim>()) - 1;
    std::array<std::uint64_t, Dim> c{};
    for (int d = 0; d < Dim; ++d) {
      const double t = (x[d] - lo_[d]) * scale_[d];
      // The negated test also sends NaN to 0: a broken particle still gets an owner and is
      // then reported by the run's finiteness check, by id.
      c[static_cast<std::size_t>(d)] =
          !(t > 0.0) ? 0 : std::min(maxCoord, static_cast<std::uint64_t>(std::min(t, 1.8e19)));
    }
    return curve_ == Curve::Hilbert ? hilbertKey<Dim>(c) : mortonKey<Dim>(c);
  }
  const Vec<Dim>& lo() const { return lo_; }
  const Vec<Dim>& hi() const { return hi_; }
  Curve curve() const { return curve_; }

private:
  Vec<Dim> lo_ = Vec<Dim>::Zero();
  Vec<Dim> hi_ = Vec<Dim>::Zero();
  Vec<Dim> scale_ = Vec<Dim>::Zero();
  Curve curve_ = Curve::Hilbert;
};

} // namespace spall::parallel
