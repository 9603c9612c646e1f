#pragma once
// A Morton (Z-order) ordering of particles: reordering the store along it keeps particles that
// are close in space close in memory, which the neighbor loops depend on for cache reuse.
#include "spall/core/Types.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

namespace spall::neighbors {

inline std::uint64_t spreadBits(std::uint64_t v, int dim) {
  std::uint64_t out = 0;
  const int bits = 63 / dim;
  for (int b = 0; b < bits; ++b) out |= ((v >> b) & 1ull) << (b * dim);
  return out;
}

template <int Dim> std::vector<std::uint32_t> mortonOrder(std::span<const Vec<Dim>> x) {
  Vec<Dim> lo = Vec<Dim>::Constant(1e300), hi = Vec<Dim>::Constant(-1e300);
  for (const auto& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const int bits = 63 / Dim;
  const double cells = static_cast<double>((1ull << bits) - 1);
  std::vector<std::uint64_t> key(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::uint64_t k = 0;
    for (int d = 0; d < Dim; ++d) {
      const double span = hi[d] - lo[d];
      const double t = span > 0.0 ? (x[i][d] - lo[d]) / span : 0.0;
      k |= spreadBits(static_cast<std::uint64_t>(t * cells), Dim) << d;
    }
    key[i] = k;
  }
  std::vector<std::uint32_t> order(x.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  return order;
}

} // namespace spall::neighbors
