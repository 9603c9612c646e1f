#pragma once
// Neighbor lists that live across steps (Verlet 1967, with a skin): a wide list, searched with
// supports 1 + skin times the step's, holds every pair the supports can reach until the
// particles have moved, or their supports grown, by more than the skin allows. Each step moves,
// in place, the pairs its own supports reach to the front of their row, with the search's own
// tests: with rows in the canonical order (sortRows) that is the row a search of that step would
// give, entry for entry, so a run's results do not depend on when the wide list was built (the
// skin, restarts, ranks). The step's list is the wide list's fronts: no second list is held.
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
#include <exception>
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
  const NeighborList& wide() const { return wide_; }
  std::span<const Vec<Dim>> builtPositions() const { return x0_; }

  // Remembers the owned particles' positions and supports when the wide list is built. H: the
  // ASPH metrics (empty for spheres).
  void record(std::span<const Vec<Dim>> x, std::span<const double> h,
              std::span<const Tensor<Dim>> H, std::size_t owned) {
    x0_.assign(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(owned));
    wide_.counts.assign(owned, 0); // every pair outside the step's rows until the next filter
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

  // The step's list, in place: each row of the wide list is split into the pairs that supports
  // `support` reach (first, the step's row: wide().of(i)) and the others (after), both in the
  // canonical order. The tests are the search's, with its expressions (NeighborList.hpp), so
  // that they decide every pair as a search would, and the step's row is the one a search of
  // that step gives. A row is rewritten only where a pair came into reach or left it (fewer rows
  // a step, all of them after a search); no second list is held.
  void filter(std::span<const Vec<Dim>> x, std::span<const double> h,
              std::span<const Tensor<Dim>> H, double support) {
    const std::size_t owned = wide_.offsets.size() - 1, n = x.size();
    resizeWithHeadroom(radius_, n);
#pragma omp parallel for schedule(static) if (threaded(n))
    for (std::size_t a = 0; a < n; ++a) radius_[a] = support * h[a];
    const bool ellipsoidal = !H.empty();
    const double support2 = support * support;
    if (ellipsoidal) {
      resizeWithHeadroom(G_, n);
      resizeWithHeadroom(inner2_, n);
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
    if (wide_.counts.size() != owned) wide_.counts.assign(owned, 0); // (not recorded)
    std::uint64_t kept = 0, longest = 0;
    for (std::size_t i = 0; i < owned; ++i)
      longest = std::max<std::uint64_t>(longest, wide_.length(i));
    // (An exception must not leave a parallel region: a failed allocation is carried out.)
    std::exception_ptr failure;
#pragma omp parallel if (threaded(owned))
    {
      // This thread's scratch: the row decoded, pairs that left reach, came into it, the others,
      // a merged row.
      std::vector<std::uint32_t> decoded, out, in, others, merged;
      try {
        for (auto* v : {&decoded, &out, &in, &others, &merged}) v->resize(longest);
      } catch (...) {
#pragma omp critical(spall_filter_failure)
        if (!failure) failure = std::current_exception();
      }
      const bool ready = merged.size() == longest;
#pragma omp for schedule(dynamic, 256) reduction(+ : kept)
      for (std::size_t i = 0; i < owned; ++i) {
        if (!ready) continue;
        std::uint32_t* row = decoded.data();
        const std::size_t length = wide_.length(i);
        wide_.decode(i, length, row);
        const std::size_t before = wide_.counts[i];
        const Vec<Dim> xi = x[i];
        const double ri2 = radius_[i] * radius_[i];
        const auto reached = [&](std::uint32_t j) {
          const Vec<Dim> d = xi - x[j];
          const double r2 = d.squaredNorm();
          if (ellipsoidal) return gathers(i, d, r2) || gathers(j, Vec<Dim>(-d), r2);
          return r2 < ri2 || r2 < radius_[j] * radius_[j];
        };
        // Without branches on the outcome (after a search a quarter of a row's pairs are out of
        // reach, at random places). The step's row keeps, in order, its pairs still in reach.
        std::size_t stay = 0, left = 0, came = 0;
        for (std::size_t k = 0; k < before; ++k) {
          const std::uint32_t j = row[k];
          const bool keep = reached(j);
          row[stay] = j, out[left] = j;
          stay += keep, left += !keep;
        }
        std::size_t rest = 0;
        for (std::size_t k = before; k < length; ++k) {
          const std::uint32_t j = row[k];
          const bool keep = reached(j);
          in[came] = j, others[rest] = j;
          came += keep, rest += !keep;
        }
        if (left == 0 && came == 0) {
          kept += before;
          continue;
        }
        // Both parts of the row again, each in the canonical order: the pairs that stayed and
        // those that came, merged by place; then the others and those that left.
        std::size_t m = merge(row, row + stay, in.data(), in.data() + came, merged.data());
        const std::size_t now = m;
        m += merge(others.data(), others.data() + rest, out.data(), out.data() + left,
                   merged.data() + m);
        wide_.rewrite(i, merged.data()); // (m = length)
        wide_.counts[i] = static_cast<std::uint32_t>(now);
        kept += now;
      }
    }
    if (failure) std::rethrow_exception(failure);
    wide_.keptPairs = kept;
  }

  // The list's row places from the search (the canonical order of its particles), when rows are
  // kept in that order; empty otherwise (then pairs coming into reach are appended).
  std::vector<std::uint32_t>& places() {
    return places_;
  }

  // The wide list and what the filter keeps beside it.
  std::size_t bytes() const {
    return wide_.bytes() + allocatedBytes(x0_, h0_, H0_, radius_, inner2_, G_, places_);
  }

private:
  double skin_;
  NeighborList wide_;
  std::vector<Vec<Dim>> x0_;
  std::vector<double> h0_;
  std::vector<Tensor<Dim>> H0_;
  // [a, ae) and [b, be) merged into `to` by place (the canonical order), or one after the other
  // without places; returns the count. b is short (the few pairs that came into reach or left
  // it; all of them when a is empty, after a search): each finds its place in a by bisection.
  std::size_t merge(const std::uint32_t* a, const std::uint32_t* ae, const std::uint32_t* b,
                    const std::uint32_t* be, std::uint32_t* to) const {
    std::uint32_t* const start = to;
    if (!places_.empty())
      for (; b != be && a != ae; ++b) {
        const std::uint32_t place = places_[*b];
        const std::uint32_t* at =
            std::partition_point(a, ae, [&](std::uint32_t v) { return places_[v] < place; });
        to = std::copy(a, at, to);
        a = at;
        *to++ = *b;
      }
    to = std::copy(a, ae, to);
    to = std::copy(b, be, to);
    return static_cast<std::size_t>(to - start);
  }
  // The filter's scratch: supports, ellipsoid metrics and inscribed spheres.
  std::vector<double> radius_, inner2_;
  std::vector<Tensor<Dim>> G_;
  std::vector<std::uint32_t> places_;
};

} // namespace spall::neighbors
