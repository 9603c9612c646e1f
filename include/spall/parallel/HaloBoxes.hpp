#pragma once
// Which ranks need a particle as a ghost, without MPI: the rule HaloExchange applies to the
// domains the ranks describe, kept here so that `spall plan` applies the very same rule to
// virtual ranks. Physics-free.
//
// A rank describes its domain by kHaloBoxes bounding boxes of consecutive owned particles
// (compact when they are in key order), each with the largest reach inside it. Particle j goes
// to rank r with periodic shift s when x_j + s lies within max(reach_j, reach_b) of one of r's
// boxes b: then every pair (i, j) with |x_i - x_j| < max(reach_i, reach_j) is complete on the
// rank that owns i, which is what the symmetric SPH sums need. With per-axis reaches (ellipsoids)
// the same test holds axis by axis.
#include "spall/core/MemoryAccounting.hpp"
#include "spall/core/Types.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace spall::parallel {

struct PeriodicAxis {
  int axis = 0;
  double min = 0.0, max = 1.0;
};

inline constexpr int kHaloBoxes = 128;

template <int Dim> struct HaloBox {
  Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::infinity());
  Vec<Dim> hi = Vec<Dim>::Constant(-std::numeric_limits<double>::infinity());
  Vec<Dim> reach = Vec<Dim>::Zero(); // largest half-width of its particles, per axis
  double radius = 0.0;               // largest radius of its particles
  bool empty() const { return !(lo[0] <= hi[0]); }
};

// The kHaloBoxes boxes of one rank's owned rows, in chunks of consecutive rows.
template <int Dim>
std::vector<HaloBox<Dim>> describeBoxes(std::span<const Vec<Dim>> x,
                                        std::span<const Vec<Dim>> reach,
                                        std::span<const double> radius) {
  std::vector<HaloBox<Dim>> boxes(kHaloBoxes);
  const std::size_t n = x.size();
  const std::size_t chunk = (n + kHaloBoxes - 1) / kHaloBoxes;
  for (int b = 0; b < kHaloBoxes; ++b) {
    HaloBox<Dim>& box = boxes[static_cast<std::size_t>(b)];
    const std::size_t begin = std::min(n, static_cast<std::size_t>(b) * chunk);
    const std::size_t end = std::min(n, begin + chunk);
    for (std::size_t i = begin; i < end; ++i) {
      if (!x[i].allFinite()) continue; // reported by the run's finiteness check, not here
      box.lo = box.lo.cwiseMin(x[i]);
      box.hi = box.hi.cwiseMax(x[i]);
      box.reach = box.reach.cwiseMax(reach[i]);
      box.radius = std::max(box.radius, radius[i]);
    }
  }
  return boxes;
}

// Slack on the reach test: the pair test r < reach is evaluated from the positions differently
// than the box distance, so a pair exactly at the edge must not be lost to rounding.
inline constexpr double kHaloSlack = 1.0 + 1e-9;

// Every rank's boxes, and the test of a particle against them.
template <int Dim> class HaloTargets {
public:
  HaloTargets() = default;
  explicit HaloTargets(std::vector<PeriodicAxis> periodic) : periodic_(std::move(periodic)) {}

  // kHaloBoxes boxes per rank, rank after rank. round: spheres only (SPH); otherwise spheres and
  // bounding boxes (ellipsoids: ASPH, MPM).
  void setBoxes(std::vector<HaloBox<Dim>> boxes, bool round) {
    boxes_ = std::move(boxes);
    round_ = round;
    const std::size_t ranks = boxes_.size() / kHaloBoxes;
    rankBox_.assign(ranks, HaloBox<Dim>{});
    reachMax_ = Vec<Dim>::Zero();
    radiusMax_ = 0.0;
    for (std::size_t k = 0; k < boxes_.size(); ++k) {
      const HaloBox<Dim>& b = boxes_[k];
      HaloBox<Dim>& u = rankBox_[k / kHaloBoxes];
      if (k % kHaloBoxes == 0) u = b;
      u.lo = u.lo.cwiseMin(b.lo);
      u.hi = u.hi.cwiseMax(b.hi);
      u.reach = u.reach.cwiseMax(b.reach);
      u.radius = std::max(u.radius, b.radius);
    }
    for (const auto& u : rankBox_) {
      reachMax_ = reachMax_.cwiseMax(u.reach);
      radiusMax_ = std::max(radiusMax_, u.radius);
    }
  }
  int ranks() const { return static_cast<int>(rankBox_.size()); }
  const HaloBox<Dim>& rankBox(int r) const { return rankBox_[static_cast<std::size_t>(r)]; }
  // The largest radius of any box.
  double radiusMax() const { return radiusMax_; }
  std::size_t bytes() const { return allocatedBytes(periodic_, boxes_, rankBox_); }

  // The periodic shift of a code: base 3 per periodic axis, 1 = +L, 2 = -L.
  Vec<Dim> shiftOf(std::uint8_t code) const {
    Vec<Dim> s = Vec<Dim>::Zero();
    for (const auto& p : periodic_) {
      const int t = code % 3;
      code = static_cast<std::uint8_t>(code / 3);
      const double L = p.max - p.min;
      if (t == 1) s[p.axis] += L;
      if (t == 2) s[p.axis] -= L;
    }
    return s;
  }

  // Calls emit(r, code) once for each rank r and periodic shift code whose domain needs the
  // particle at xj (reach per axis, radius) as a ghost; `self` (its owner) only for non-zero
  // shifts. candidates(xs, visit) calls visit(r) for every rank whose domain may be near the
  // position xs (in ascending order for a reproducible plan; every rank will do).
  template <class Candidates, class Emit>
  void targets(const Vec<Dim>& xj, const Vec<Dim>& reachj, double radiusj, int self,
               Candidates&& candidates, Emit&& emit) const {
    if (!xj.allFinite()) return;
    // Periodic images worth testing: along each periodic axis, +L near min and -L near max;
    // the codes in mixed radix, the first axis fastest (the order of the ghosts).
    std::array<std::array<std::uint8_t, 3>, 3> option{};
    std::array<int, 3> options{1, 1, 1};
    int axes = 0;
    std::uint8_t weight = 1;
    for (const auto& p : periodic_) {
      const double far = std::max(reachMax_[p.axis], reachj[p.axis]) * kHaloSlack;
      auto& o = option[static_cast<std::size_t>(axes)];
      int& m = options[static_cast<std::size_t>(axes)];
      if (xj[p.axis] - p.min < far) o[static_cast<std::size_t>(m++)] = weight;
      if (p.max - xj[p.axis] <= far)
        o[static_cast<std::size_t>(m++)] = static_cast<std::uint8_t>(2 * weight);
      weight = static_cast<std::uint8_t>(weight * 3);
      ++axes;
    }
    std::array<int, 3> digit{};
    for (bool more = true; more;) {
      std::uint8_t code = 0;
      for (int a = 0; a < axes; ++a)
        code = static_cast<std::uint8_t>(
            code + option[static_cast<std::size_t>(a)]
                         [static_cast<std::size_t>(digit[static_cast<std::size_t>(a)])]);
      const Vec<Dim> xs = code ? Vec<Dim>(xj + shiftOf(code)) : xj;
      more = false;
      for (int a = 0; a < axes; ++a) {
        auto& d = digit[static_cast<std::size_t>(a)];
        if (++d < options[static_cast<std::size_t>(a)]) {
          more = true;
          break;
        }
        d = 0;
      }
      candidates(xs, [&](int r) {
        if (r == self && code == 0) return;
        const HaloBox<Dim>& u = rankBox_[static_cast<std::size_t>(r)];
        if (u.empty() || !near(xs, reachj, radiusj, u)) return;
        for (int b = 0; b < kHaloBoxes; ++b) {
          const HaloBox<Dim>& box = boxes_[static_cast<std::size_t>(r * kHaloBoxes + b)];
          if (!box.empty() && near(xs, reachj, radiusj, box)) {
            emit(r, code);
            return;
          }
        }
      });
    }
  }

private:
  // j reaches box b, or a particle in b reaches j: within the larger of both radii, and for
  // ellipsoids also within the larger of both half-widths along every axis (an ellipsoid lies
  // inside both its enclosing sphere and its bounding box).
  bool near(const Vec<Dim>& xs, const Vec<Dim>& reachj, double radiusj,
            const HaloBox<Dim>& b) const {
    const double rr = std::max(radiusj, b.radius) * kHaloSlack;
    double d2 = 0.0;
    for (int d = 0; d < Dim; ++d) {
      const double e = std::max({b.lo[d] - xs[d], 0.0, xs[d] - b.hi[d]});
      d2 += e * e;
    }
    if (d2 >= rr * rr) return false;
    if (round_) return true;
    // Per-axis reach (bounding boxes of ellipsoids): every axis' distance to the box within its
    // reach. (A pair (i, j) with x_j in i's ellipsoid has |x_j - x_i|_d within i's half-width
    // along every axis d, so x_j is within the box's largest half-widths of the box.)
    const Vec<Dim> r = reachj.cwiseMax(b.reach) * kHaloSlack;
    for (int d = 0; d < Dim; ++d)
      if (std::max({b.lo[d] - xs[d], 0.0, xs[d] - b.hi[d]}) >= r[d]) return false;
    return true;
  }

  std::vector<PeriodicAxis> periodic_;
  bool round_ = true;
  std::vector<HaloBox<Dim>> boxes_;   // kHaloBoxes per rank; empty boxes have lo > hi
  std::vector<HaloBox<Dim>> rankBox_; // union per rank
  Vec<Dim> reachMax_ = Vec<Dim>::Zero();
  double radiusMax_ = 0.0;
};

} // namespace spall::parallel
