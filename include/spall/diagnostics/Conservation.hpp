#pragma once
// Global conserved totals: mass, momentum, kinetic and internal energy (history.csv).
#include "spall/core/ParticleFields.hpp"
#include "spall/diagnostics/OrderFreeSums.hpp"
#include "spall/parallel/Mpi.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

namespace spall::diagnostics {

struct Totals {
  double mass = 0.0;
  std::array<double, 3> momentum{0.0, 0.0, 0.0};
  double kinetic = 0.0;
  double internal = 0.0;
  // sum of |m v| per component: the scale against which momentum errors are judged when the
  // total momentum itself is zero (Sod, Noh)
  std::array<double, 3> momentumScale{0.0, 0.0, 0.0};
  double total() const { return kinetic + internal; }
};

template <int Dim>
Totals computeTotals(const ParticleStore& s, const ParticleFields<Dim>& f,
                     const parallel::MpiContext& mpi) {
  const auto m = s[f.m];
  const auto v = s[f.v];
  const auto e = s[f.e];
  const auto t = orderFreeSums<9>(
      s.localCount(),
      [&](std::size_t i, std::span<double> term) {
        std::fill(term.begin(), term.end(), 0.0);
        term[0] = m[i];
        for (int d = 0; d < Dim; ++d) {
          term[1 + static_cast<std::size_t>(d)] = m[i] * v[i][d];
          term[4 + static_cast<std::size_t>(d)] = std::abs(m[i] * v[i][d]);
        }
        term[7] = 0.5 * m[i] * v[i].squaredNorm();
        term[8] = m[i] * e[i];
      },
      mpi.comm());
  Totals r;
  r.mass = t[0];
  for (int d = 0; d < 3; ++d) {
    r.momentum[static_cast<std::size_t>(d)] = t[1 + static_cast<std::size_t>(d)];
    r.momentumScale[static_cast<std::size_t>(d)] = t[4 + static_cast<std::size_t>(d)];
  }
  r.kinetic = t[7];
  r.internal = t[8];
  return r;
}

} // namespace spall::diagnostics
