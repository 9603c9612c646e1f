#pragma once
// Global conserved totals: mass, momentum, kinetic and internal energy (history.csv).
#include "spall/core/ParticleFields.hpp"
#include "spall/parallel/Mpi.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

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

// Sums of per-particle terms that do not depend on the terms' order: each quantity's terms are
// scaled by the power of two that brings its largest magnitude over all ranks below 2^62,
// truncated to 64-bit integers and added exactly in 128 bits, on every rank and then over all
// ranks. So the totals are the same bit for bit however the particles are stored, on any number
// of ranks and threads (a rank's storage order changes when particles migrate or are sorted,
// which kept neighbor lists make depend on the run's history). Each term keeps 62 bits relative
// to the largest: finer than a double sum's rounding. A quantity with a non-finite term is
// summed as plain doubles (the run's finiteness check names the particle).
__extension__ typedef __int128 Int128; // GCC's and Clang's 128-bit integer

template <std::size_t N, class Terms>
std::array<double, N> orderFreeSums(std::size_t n, const Terms& terms, MPI_Comm comm) {
  std::array<double, N> largest{}, t{};
  for (std::size_t i = 0; i < n; ++i) {
    terms(i, t);
    for (std::size_t q = 0; q < N; ++q) largest[q] = std::max(largest[q], std::abs(t[q]));
  }
  MPI_Allreduce(MPI_IN_PLACE, largest.data(), static_cast<int>(N), MPI_DOUBLE, MPI_MAX, comm);
  std::array<double, N> scale{};
  for (std::size_t q = 0; q < N; ++q) {
    int e = 0;
    if (std::isfinite(largest[q]) && largest[q] > 0.0) std::frexp(largest[q], &e); // < 2^e
    scale[q] = std::isfinite(largest[q]) ? std::ldexp(1.0, 62 - e) : 0.0;
  }
  std::array<Int128, N> fixed{};
  std::array<double, N> plain{};
  for (std::size_t i = 0; i < n; ++i) {
    terms(i, t);
    for (std::size_t q = 0; q < N; ++q) {
      if (scale[q] > 0.0)
        fixed[q] += static_cast<std::int64_t>(t[q] * scale[q]);
      else
        plain[q] += t[q];
    }
  }
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<Int128> all(N * static_cast<std::size_t>(ranks));
  MPI_Allgather(fixed.data(), static_cast<int>(N * sizeof(Int128)), MPI_BYTE, all.data(),
                static_cast<int>(N * sizeof(Int128)), MPI_BYTE, comm);
  MPI_Allreduce(MPI_IN_PLACE, plain.data(), static_cast<int>(N), MPI_DOUBLE, MPI_SUM, comm);
  std::array<double, N> out{};
  for (std::size_t q = 0; q < N; ++q) {
    if (!(scale[q] > 0.0)) {
      out[q] = plain[q];
      continue;
    }
    Int128 sum = 0;
    for (int r = 0; r < ranks; ++r) sum += all[static_cast<std::size_t>(r) * N + q];
    out[q] = static_cast<double>(sum) / scale[q];
  }
  return out;
}

template <int Dim>
Totals computeTotals(const ParticleStore& s, const ParticleFields<Dim>& f,
                     const parallel::MpiContext& mpi) {
  const auto m = s[f.m];
  const auto v = s[f.v];
  const auto e = s[f.e];
  const auto t = orderFreeSums<9>(
      s.localCount(),
      [&](std::size_t i, std::array<double, 9>& term) {
        term.fill(0.0);
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
