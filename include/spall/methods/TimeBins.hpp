#pragma once
// Hierarchical time steps in power-of-two bins: block time steps (Makino 1991) with Saitoh &
// Makino's (2009) neighbor limiter, as SWIFT and SPH-EXA step hydrodynamics. A step of the run
// is 2^K substeps of the finest step delta; a particle in bin k takes 2^k substeps at a time,
// from a substep that is a multiple of 2^k. Its bin comes from its own stable step, at most 2
// above any neighbor's (their steps differ by at most a factor of 4), and a particle whose
// neighbor falls to a bin more than 2 below its own is woken: its step ends at the neighbor's
// next multiple of 2^(k_j + 2). Physics-free: the method supplies the stable steps, the lists
// and the ghosts' bins (methods/SphMethod.cpp).
#include "spall/neighbors/NeighborList.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

namespace spall::methods::bins {

// Neighbors' bins differ by at most this (Saitoh & Makino 2009: steps within a factor of 4).
inline constexpr int kSpread = 2;

// A run's step ends early (every particle closing its step) where some particle's own stable
// step falls below this fraction of the finest bin's: its Courant number doubled until then.
// Ending at any fall, the steps of a penetration ended after 2 substeps: no hierarchy formed.
inline constexpr double kCloseBelow = 0.5;

// The bin of a particle whose own stable step is dt: the largest k < count with delta 2^k <= dt
// (0 when even delta exceeds it). Doublings of delta are exact: the same bin on any machine.
inline int binOf(double dt, double delta, int count) {
  int k = 0;
  for (double step = 2.0 * delta; k + 1 < count && step <= dt; step *= 2.0) ++k;
  return k;
}

// The largest bin a step starting at substep s (of a step of 2^K) can have: s a multiple of 2^k.
inline int alignedBin(std::int32_t s, int K) {
  return s == 0 ? K : std::min(K, std::countr_zero(static_cast<std::uint32_t>(s)));
}

// The end of the step of a particle woken at substep s to bin k: the first multiple of 2^k after s.
inline std::int32_t wakeEnd(std::int32_t s, int k) {
  const std::int32_t p = std::int32_t{1} << k;
  return (s / p + 1) * p;
}

// The smallest bin among row i's neighbors, `none` for none. The step's pairs (a kept list's
// first count(i)): what a search gives now, the same on any rank count; a kept list's pairs
// beyond them reach ghosts that another decomposition need not hold.
inline int neighborsBin(const neighbors::NeighborList& nl, std::size_t i,
                        std::span<const std::int32_t> bin, std::vector<std::uint32_t>& buf,
                        int none) {
  int lowest = none;
  for (std::uint32_t j : nl.of(i, buf)) lowest = std::min(lowest, int{bin[j]});
  return lowest;
}

// The fastest approach among row i's neighbors (the step's pairs, as neighborsBin):
// max_j -(v_i - v_j) . (x_i - x_j) / |x_i - x_j|, 0 when none approaches. A pair's viscosity
// acts on it at once (mu_ij), but a particle's own step sees it only at its next evaluation.
template <class Vec>
double approachSpeed(const neighbors::NeighborList& nl, std::size_t i, std::span<const Vec> x,
                     std::span<const Vec> v, std::vector<std::uint32_t>& buf) {
  double fastest = 0.0;
  for (std::uint32_t j : nl.of(i, buf)) {
    const Vec xij = x[i] - x[j];
    const double r = xij.norm();
    if (r > 0.0) fastest = std::max(fastest, -(v[i] - v[j]).dot(xij) / r);
  }
  return fastest;
}

// One sweep of the limiter over the owned rows: next_i = min(bin_i, lowest neighbor + kSpread),
// read from `bin` as it is (rows and ghosts), so that the rows' order does not matter. Returns
// whether any row changed; the caller sends the ghosts the new bins and sweeps again until none
// does on any rank (a sweep moves the limit one neighbor further).
inline bool limitSweep(const neighbors::NeighborList& nl, std::size_t owned,
                       std::span<const std::int32_t> bin, std::span<std::int32_t> next) {
  bool changed = false;
  std::vector<std::uint32_t> buf;
  for (std::size_t i = 0; i < owned; ++i) {
    const int limit = neighborsBin(nl, i, bin, buf, bin[i]) + kSpread;
    next[i] = std::min(bin[i], limit);
    changed = changed || next[i] != bin[i];
  }
  return changed;
}

} // namespace spall::methods::bins
