#pragma once
// Sums of per-particle terms that do not depend on the terms' order: each quantity's terms are
// scaled by the power of two that brings its largest magnitude over all ranks below 2^62,
// rounded to 64-bit integers and added exactly in 128 bits (FixedPoint), on every rank and then
// over all ranks. So the totals are the same bit for bit however the particles are stored, on any
// number of ranks and threads (a rank's storage order changes when particles migrate or are sorted,
// which kept neighbor lists make depend on the run's history). Each term keeps 62 bits relative
// to the largest: finer than a double sum's rounding (a quantity with one nonzero term is that
// term exactly). A quantity with a non-finite term is summed as plain doubles (the run's
// finiteness check names the particle).
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace spall::diagnostics {

__extension__ typedef __int128 Int128; // GCC's and Clang's 128-bit integer

// Exact, order-independent sums of one quantity: each term is rounded once to a multiple of
// 2^-E, E chosen so that the largest magnitude (over all ranks) is below 2^62, and summed in
// 128-bit integers (room for 2^64 terms). Terms below 2^-62 of the largest lose their last bits
// identically on every rank count; a single nonzero term comes back exactly.
class FixedPoint {
public:
  explicit FixedPoint(double largest = 1.0) {
    int e = 0;
    std::frexp(largest > 0.0 ? largest : 1.0, &e); // largest < 2^e
    E_ = 62 - e;
    scale_ = E_ > -1000 && E_ < 1000 ? std::ldexp(1.0, E_) : 0.0;
  }
  // llround(ldexp(x, E)), inline: a product by 2^E rounds as ldexp does (once, the same result),
  // and the rounding half away from zero from the truncation and the exact remainder (the
  // library calls were 3% of a 2D step's time, a history row every step).
  Int128 of(double x) const {
    const double y = scale_ != 0.0 ? x * scale_ : std::ldexp(x, E_);
    if (!(std::abs(y) < 0x1p62)) return static_cast<Int128>(std::llround(y));
    const auto t = static_cast<std::int64_t>(y);    // truncated
    const double rest = y - static_cast<double>(t); // exact
    return static_cast<Int128>(t + (rest >= 0.5) - (rest <= -0.5));
  }
  double value(Int128 q) const { return std::ldexp(static_cast<double>(q), -E_); }

private:
  int E_ = 0;
  double scale_ = 0.0; // 2^E where it is a normal double
};

// `count` quantities over n terms: terms(i, t) writes term i of each quantity into t (a span of
// `count`); the totals, the same on every rank.
template <class Terms>
std::vector<double> orderFreeSums(std::size_t n, std::size_t count, const Terms& terms,
                                  MPI_Comm comm) {
  std::vector<double> largest(count, 0.0), t(count, 0.0), plain(count, 0.0);
  const std::span<double> term(t);
  for (std::size_t i = 0; i < n; ++i) {
    terms(i, term);
    for (std::size_t q = 0; q < count; ++q) largest[q] = std::max(largest[q], std::abs(t[q]));
  }
  const int c = static_cast<int>(count);
  MPI_Allreduce(MPI_IN_PLACE, largest.data(), c, MPI_DOUBLE, MPI_MAX, comm);
  std::vector<FixedPoint> scale(count);
  std::vector<std::uint8_t> exact(count, 0); // finite: summed in fixed point
  for (std::size_t q = 0; q < count; ++q)
    if (std::isfinite(largest[q])) exact[q] = 1, scale[q] = FixedPoint(largest[q]);
  std::vector<Int128> fixed(count, 0);
  for (std::size_t i = 0; i < n; ++i) {
    terms(i, term);
    for (std::size_t q = 0; q < count; ++q) {
      if (exact[q])
        fixed[q] += scale[q].of(t[q]);
      else
        plain[q] += t[q];
    }
  }
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<Int128> all(count * static_cast<std::size_t>(ranks));
  const int bytes = static_cast<int>(count * sizeof(Int128));
  MPI_Allgather(fixed.data(), bytes, MPI_BYTE, all.data(), bytes, MPI_BYTE, comm);
  MPI_Allreduce(MPI_IN_PLACE, plain.data(), c, MPI_DOUBLE, MPI_SUM, comm);
  std::vector<double> out(count, 0.0);
  for (std::size_t q = 0; q < count; ++q) {
    if (!exact[q]) {
      out[q] = plain[q];
      continue;
    }
    Int128 sum = 0;
    for (int r = 0; r < ranks; ++r) sum += all[static_cast<std::size_t>(r) * count + q];
    out[q] = scale[q].value(sum);
  }
  return out;
}

// N quantities known at compile time: terms(i, t) writes into a std::span<double> of N.
template <std::size_t N, class Terms>
std::array<double, N> orderFreeSums(std::size_t n, const Terms& terms, MPI_Comm comm) {
  const auto sums = orderFreeSums(n, N, terms, comm);
  std::array<double, N> out{};
  std::copy(sums.begin(), sums.end(), out.begin());
  return out;
}

} // namespace spall::diagnostics
