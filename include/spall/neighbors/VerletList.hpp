#pragma once
// Neighbor lists that live across steps (Verlet 1967, with a skin): a wide list, searched with
// supports 1 + skin times the step's, holds every pair the supports can reach until the
// particles have moved, or their supports grown, by more than the skin allows. Each step keeps,
// in list order, the pairs its own supports reach, with the search's own tests: with rows in the
// canonical order (sortRows) that is the list a search of that step would give, entry for entry,
// so a run's results do not depend on when the wide list was built (the skin, restarts, ranks).
//
// When to build it again. A pair (a, b) is in the step's list when a support covers the other,
// say |H_a d| < k (k the support radius in units of H, d = x_b - x_a; spheres: H = I / h). With
// d0, H0 at the wide build and delta the displacements since,
//   |H0_a d0| <= |H0_a H_a^-1| |H_a d| + |H0_a| (delta_a + delta_b)
//             <  k (1 + g_a + delta_a |H0_a| / k + delta_b |H0_a| / k),  g_a = |H0_a H_a^-1| - 1,
// and the wide list has every pair with |H0_a d0| < k (1 + skin). It is complete while
//   max_a (g_a + delta_a |H0_a| / k) + max_b delta_b * max_a |H0_a| / k < skin
// over all particles of all ranks (three maxima: one reduction). For ellipsoids the norms are
// bounded from above: |M|_2 <= sqrt(|M|_1 |M|_inf), |H0|_2 <= |H0|_inf; spheres have them exact.
#include "spall/core/Threads.hpp"
#include "spall/core/Types.hpp"
#include "spall/neighbors/NeighborList.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

namespace spall::neighbors {

template <int Dim> class VerletList {
public:
  explicit VerletList(double skin) : skin_(skin) {}

  double skin() const { return skin_; }
  // The support the wide list is searched with.
  double widened(double support) const { return support * (1.0 + skin_); }
  NeighborList& wide() { return wide_; }
  std::span<const Vec<Dim>> builtPositions() const { return x0_; }

  // Remembers the owned particles' positions and supports when the wide list is built. H: the
  // ASPH metrics (empty for spheres).
  void record(std::span<const Vec<Dim>> x, std::span<const double> h,
              std::span<const Tensor<Dim>> H, std::size_t owned) {
    x0_.assign(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(owned));
    if (H.empty()) {
      h0_.assign(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(owned));
      H0_.clear();
    } else {
      H0_.assign(H.begin(), H.begin() + static_cast<std::ptrdiff_t>(owned));
      h0_.clear();
    }
  }

  // This rank's share of the test above: {max_a (g_a + delta_a |H0_a| / k), max_a delta_a,
  // max_a |H0_a| / k} over the owned particles recorded (infinite if any is not finite).
  std::array<double, 3> drift(std::span<const Vec<Dim>> x, std::span<const double> h,
                              std::span<const Tensor<Dim>> H, double support) const {
    const std::size_t n = x0_.size();
    double consumed = 0.0, moved = 0.0, reach = 0.0;
    const bool aniso = !H0_.empty();
#pragma omp parallel for schedule(static) reduction(max : consumed, moved, reach) if (threaded(n))
    for (std::size_t a = 0; a < n; ++a) {
      const double delta = (x[a] - x0_[a]).norm();
      double growth, k0;
      if (aniso) {
        const Tensor<Dim> M = H0_[a] * H[a].inverse();
        growth = std::sqrt(M.cwiseAbs().colwise().sum().maxCoeff() *
                           M.cwiseAbs().rowwise().sum().maxCoeff()) -
                 1.0;
        k0 = H0_[a].cwiseAbs().rowwise().sum().maxCoeff() / support;
      } else {
        growth = h[a] / h0_[a] - 1.0;
        k0 = 1.0 / (h0_[a] * support);
      }
      double c = growth + delta * k0;
      if (!std::isfinite(c) || !std::isfinite(delta)) c = std::numeric_limits<double>::infinity();
      consumed = std::max(consumed, c);
      moved = std::max(moved, delta);
      reach = std::max(reach, k0);
    }
    return {consumed, moved, reach};
  }

  // Whether the wide list still holds every pair, given the maxima over all ranks (a margin of a
  // millionth of the skin covers the rounding of the bound).
  bool holds(const std::array<double, 3>& m) const {
    return m[0] + m[1] * m[2] < skin_ * (1.0 - 1e-6);
  }

  // The pairs of the wide list that supports `support` reach, in its order: the search's tests
  // with the search's expressions (NeighborList.hpp), so that they decide every pair as a search
  // would. Rows in parallel chunks, each written at its place in the wide list, then joined.
  void filter(std::span<const Vec<Dim>> x, std::span<const double> h,
              std::span<const Tensor<Dim>> H, double support, NeighborList& out) {
    const std::size_t owned = wide_.offsets.size() - 1, n = x.size();
    radius_.resize(n);
    for (std::size_t a = 0; a < n; ++a) radius_[a] = support * h[a];
    const bool ellipsoidal = !H.empty();
    const double support2 = support * support;
    if (ellipsoidal) {
      G_.resize(n);
      inner2_.resize(n);
#pragma omp parallel for schedule(static) if (threaded(n))
      for (std::size_t a = 0; a < n; ++a) {
        G_[a] = H[a].transpose() * H[a];
        const double rin = support / H[a].cwiseAbs().rowwise().sum().maxCoeff();
        inner2_[a] = rin * rin;
      }
    }
    // p's support covers q (an ellipsoid: its enclosing sphere, then the inscribed sphere or the
    // quadratic form), d = x_p - x_q.
    const auto gathers = [&](std::size_t p, const Vec<Dim>& d, double r2) {
      if (!(r2 < radius_[p] * radius_[p] * (1.0 + 1e-9))) return false;
      return r2 < inner2_[p] || d.dot(G_[p] * d) < support2;
    };
    out.offsets.resize(owned + 1);
    out.offsets[0] = 0;
    out.indices.resize(wide_.indices.size());
    const std::size_t chunks =
        threadCount() == 1 || !threaded(owned) ? 1 : 32 * static_cast<std::size_t>(threadCount());
    used_.assign(chunks, 0);
    std::uint32_t* list = out.indices.data();
#pragma omp parallel for schedule(dynamic, 1) if (threaded(owned))
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::size_t b = chunkBegin(owned, chunks, c), e = chunkBegin(owned, chunks, c + 1);
      std::uint64_t write = wide_.offsets[b];
      for (std::size_t i = b; i < e; ++i) {
        const Vec<Dim> xi = x[i];
        const double ri2 = radius_[i] * radius_[i];
        for (std::uint64_t k = wide_.offsets[i]; k < wide_.offsets[i + 1]; ++k) {
          const std::uint32_t j = wide_.indices[k];
          const Vec<Dim> d = xi - x[j];
          const double r2 = d.squaredNorm();
          bool keep;
          if (ellipsoidal)
            keep = gathers(i, d, r2) || gathers(j, Vec<Dim>(-d), r2);
          else
            keep = r2 < ri2 || r2 < radius_[j] * radius_[j];
          list[write] = j;
          write += keep;
        }
        out.offsets[i + 1] = write;
      }
      used_[c] = write - wide_.offsets[b];
    }
    // Chunk c's rows move down to right after chunk c - 1's (never past their own start).
    std::uint64_t base = 0;
    shift_.resize(chunks);
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::uint64_t start = wide_.offsets[chunkBegin(owned, chunks, c)];
      if (base != start) std::memmove(list + base, list + start, used_[c] * sizeof(std::uint32_t));
      shift_[c] = start - base;
      base += used_[c];
    }
#pragma omp parallel for schedule(static) if (threaded(owned))
    for (std::size_t c = 0; c < chunks; ++c)
      for (std::size_t i = chunkBegin(owned, chunks, c); i < chunkBegin(owned, chunks, c + 1); ++i)
        out.offsets[i + 1] -= shift_[c];
    out.indices.resize(base);
  }

  // Bytes held per owned particle beyond the step's list: the wide list and the positions and
  // supports of its build.
  std::size_t bytes() const {
    return wide_.indices.capacity() * sizeof(std::uint32_t) +
           wide_.offsets.capacity() * sizeof(std::uint64_t) + x0_.capacity() * sizeof(Vec<Dim>) +
           h0_.capacity() * sizeof(double) + H0_.capacity() * sizeof(Tensor<Dim>);
  }

private:
  double skin_;
  NeighborList wide_;
  std::vector<Vec<Dim>> x0_;
  std::vector<double> h0_;
  std::vector<Tensor<Dim>> H0_;
  // The filter's scratch: supports, ellipsoid metrics and inscribed spheres, chunk bookkeeping.
  std::vector<double> radius_, inner2_;
  std::vector<Tensor<Dim>> G_;
  std::vector<std::uint64_t> used_, shift_;
};

} // namespace spall::neighbors
