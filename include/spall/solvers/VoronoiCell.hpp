#pragma once
// A particle's Voronoi cell among its neighbors, its part symmetric about the particle, and its
// volume and second moment: the shape of the local node distribution, read without any smoothing
// scale (solvers/IdealH.hpp takes the ASPH ellipse's shape from it). Geometry only: offsets
// relative to the particle at the origin.
//
// The cell starts as a cube (square) around the origin and is cut by each neighbor's bisector,
// x . d <= |d|^2 / 2 for the offset d (a neighbor farther than twice the cell's farthest corner
// can no longer cut it), then by the bisectors that cut it mirrored through the particle
// (voronoiCell says why). A corner left on the starting cube means that no neighbor bounds the
// cell on either side along some direction: the cell is open.
#include "spall/core/Types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace spall::solvers {

template <int Dim> struct CellMoments {
  double volume = 0.0;
  Vec<Dim> centroid = Vec<Dim>::Zero();     // relative to the particle
  Tensor<Dim> second = Tensor<Dim>::Zero(); // about the centroid, per unit volume
};

// The moments from the cell's sums: its volume, first moment m1 and second moment m2 about the
// particle.
template <int Dim>
CellMoments<Dim> cellMoments(double volume, const Vec<Dim>& m1, const Tensor<Dim>& m2) {
  CellMoments<Dim> out;
  out.volume = volume;
  if (volume <= 0.0) return out;
  out.centroid = m1 / volume;
  out.second = m2 / volume - out.centroid * out.centroid.transpose();
  return out;
}

template <int Dim> class VoronoiCell;

// A cut that would take off no more than this fraction of the plane's distance c/|n| is not
// made: on a nearly regular lattice many bisectors, and the mirrored ones, pass within a hair
// of corners, edges and faces, and the slivers they would cut add corners to every later clip
// (3D: 40% of the cell's cost on a lattice displaced by 1e-3 of its spacing) for a change in
// the moments of that order or less (measured there: 7e-5 of the volume).
inline constexpr double kSliver = 1e-3;

// The signed distances x(k) . n - c of the count corners into dist, and whether the plane cuts
// deeper than a sliver.
template <class Position, class Normal>
bool cutsDeeperThanSliver(std::size_t count, Position x, const Normal& n, double c,
                          std::vector<double>& dist) {
  dist.resize(count);
  double dMax = -1.0;
  for (std::size_t k = 0; k < count; ++k) dist[k] = x(k).dot(n) - c, dMax = std::max(dMax, dist[k]);
  return dMax > kSliver * std::abs(c);
}

// 1D: an interval (ASPH in 1D is SPH; the cell is there so that every dimension has one).
template <> class VoronoiCell<1> {
public:
  void reset(double halfWidth) { a_ = halfWidth, lo_ = -halfWidth, hi_ = halfWidth; }
  bool clip(const Vec<1>& n, double c) {
    if (n[0] > 0.0 && c / n[0] < hi_) return hi_ = c / n[0], true;
    if (n[0] < 0.0 && c / n[0] > lo_) return lo_ = c / n[0], true;
    return false;
  }
  bool clipByNeighbor(const Vec<1>& d) { return clip(d, 0.5 * d.squaredNorm()); }
  double farthestCorner2() const { return std::max(lo_ * lo_, hi_ * hi_); }
  bool open() const { return lo_ == -a_ || hi_ == a_; }
  CellMoments<1> moments() const {
    CellMoments<1> out;
    out.volume = hi_ - lo_;
    out.centroid[0] = 0.5 * (lo_ + hi_);
    out.second(0, 0) = out.volume * out.volume / 12.0;
    return out;
  }

private:
  double a_ = 0.0, lo_ = 0.0, hi_ = 0.0;
};

template <> class VoronoiCell<2> {
public:
  void reset(double halfWidth) {
    a_ = halfWidth;
    v_ = {Vec<2>(-a_, -a_), Vec<2>(a_, -a_), Vec<2>(a_, a_), Vec<2>(-a_, a_)};
    r2Max_ = 2.0 * a_ * a_;
  }
  // Keeps the part with x . n <= c (Sutherland-Hodgman on the one polygon: each corner decided
  // once). False if nothing is cut.
  bool clip(const Vec<2>& n, double c) {
    const std::size_t m = v_.size();
    if (!cutsDeeperThanSliver(
            m, [&](std::size_t k) { return v_[k]; }, n, c, dist_))
      return false;
    w_.clear();
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t l = (k + 1) % m;
      const double da = dist_[k], db = dist_[l];
      if (da <= 0.0) w_.push_back(v_[k]);
      // Clamped against round-off: the crossing stays on the edge.
      if ((da <= 0.0) != (db <= 0.0))
        w_.push_back(v_[k] + std::clamp(da / (da - db), 0.0, 1.0) * (v_[l] - v_[k]));
    }
    v_.swap(w_);
    r2Max_ = 0.0;
    for (const auto& p : v_) r2Max_ = std::max(r2Max_, p.squaredNorm());
    return true;
  }
  bool clipByNeighbor(const Vec<2>& d) { return clip(d, 0.5 * d.squaredNorm()); }
  double farthestCorner2() const { return r2Max_; }
  // Some corner still on the starting box (crossings along a box side keep its coordinate
  // exactly): no neighbor bounds the cell there.
  bool open() const {
    for (const auto& p : v_)
      if (p.cwiseAbs().maxCoeff() == a_) return true;
    return false;
  }
  // Triangles (0, a, b): area |a x b|/2, first moment area (a+b)/3, second area/12 (a a^T +
  // b b^T + (a+b)(a+b)^T); the origin is inside the cell, so every triangle counts positive.
  CellMoments<2> moments() const {
    Vec<2> m1 = Vec<2>::Zero();
    Tensor<2> m2 = Tensor<2>::Zero();
    double twiceArea = 0.0;
    const std::size_t m = v_.size();
    for (std::size_t k = 0; k < m; ++k) {
      const Vec<2>& a = v_[k];
      const Vec<2>& b = v_[(k + 1) % m];
      const double A2 = std::abs(a[0] * b[1] - a[1] * b[0]);
      const Vec<2> s = a + b;
      twiceArea += A2;
      m1 += (A2 / 6.0) * s;
      m2 += (A2 / 24.0) * (a * a.transpose() + b * b.transpose() + s * s.transpose());
    }
    return cellMoments<2>(0.5 * twiceArea, m1, m2);
  }

private:
  std::vector<Vec<2>> v_, w_;
  std::vector<double> dist_;
  double a_ = 0.0, r2Max_ = 0.0;
};

template <> class VoronoiCell<3> {
public:
  // The cube's corners (bit k set: +a along axis k), each with its three neighbors ordered
  // counterclockwise seen from outside.
  void reset(double halfWidth) {
    a_ = halfWidth;
    v_.clear();
    for (std::uint32_t c = 0; c < 8; ++c) {
      const Vec<3> s(c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : -1.0);
      Corner k{a_ * s, {c ^ 1u, c ^ 2u, c ^ 4u}};
      if (s.prod() < 0.0) std::swap(k.nb[1], k.nb[2]);
      v_.push_back(k);
    }
    r2Max_ = 3.0 * a_ * a_;
  }
  // Keeps the part with x . n <= c (after Powell & Abel's r3d clip, 2015: every corner has three
  // edges; a corner where more planes meet is several corners at one point). Each corner is
  // decided once (kept: n . x <= c), each edge from a kept corner to a cut one gets a new corner
  // where it crosses the plane, and the new corners are linked around the new face by walking
  // each cut face from one to the next: the cell stays a closed surface whatever the round-off,
  // however near the plane passes to corners, edges or other faces. False if nothing is cut.
  bool clip(const Vec<3>& n, double c) {
    const std::size_t old = v_.size();
    if (!cutsDeeperThanSliver(
            old, [&](std::size_t k) { return v_[k].x; }, n, c, dist_))
      return false;
    for (std::uint32_t k = 0; k < old; ++k) {
      if (dist_[k] > 0.0) continue;
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t u = v_[k].nb[e];
        if (u >= old || dist_[u] <= 0.0) continue;
        // Clamped against round-off: the crossing stays on the edge.
        const double t = std::clamp(dist_[k] / (dist_[k] - dist_[u]), 0.0, 1.0);
        const Vec<3> x = v_[k].x + t * (v_[u].x - v_[k].x);
        v_[k].nb[e] = static_cast<std::uint32_t>(v_.size());
        v_.push_back({x, {k, kNone, kNone}});
      }
    }
    // Link each new corner to the next one around the face that its kept neighbor's next edge
    // bounds.
    for (std::uint32_t w = static_cast<std::uint32_t>(old); w < v_.size(); ++w) {
      std::uint32_t at = w, next = v_[w].nb[0];
      do {
        const int e = slotOf(next, at);
        at = next;
        next = v_[at].nb[(e + 1) % 3];
      } while (at < old);
      v_[w].nb[2] = at;
      v_[at].nb[1] = w;
    }
    // Drop the cut corners.
    remap_.assign(v_.size(), kNone);
    std::uint32_t kept = 0;
    for (std::uint32_t k = 0; k < v_.size(); ++k)
      if (k >= old || dist_[k] <= 0.0) remap_[k] = kept++;
    for (std::uint32_t k = 0; k < v_.size(); ++k) {
      if (remap_[k] == kNone) continue;
      Corner moved = v_[k];
      for (auto& u : moved.nb) u = remap_[u];
      v_[remap_[k]] = moved;
    }
    v_.resize(kept);
    r2Max_ = 0.0;
    for (const auto& k : v_) r2Max_ = std::max(r2Max_, k.x.squaredNorm());
    return true;
  }
  bool clipByNeighbor(const Vec<3>& d) { return clip(d, 0.5 * d.squaredNorm()); }
  double farthestCorner2() const { return r2Max_; }
  // Some corner still on the starting box (crossings along a box face keep its coordinate
  // exactly): no neighbor bounds the cell there.
  bool open() const {
    for (const auto& k : v_)
      if (k.x.cwiseAbs().maxCoeff() == a_) return true;
    return false;
  }
  // Tetrahedra (0, c, a, b) for each edge (a, b) of each face, c the mean of its corners: volume
  // |det|/6, first moment volume (c + a + b)/4, second volume/20 (sum of p p^T over the corners +
  // s s^T, s their sum); the origin is inside the cell, so every tetrahedron counts positive.
  // Each face is walked once, from an edge not yet walked.
  CellMoments<3> moments() const {
    Vec<3> m1 = Vec<3>::Zero();
    Tensor<3> m2 = Tensor<3>::Zero();
    double sixVolume = 0.0;
    walked_.assign(3 * v_.size(), 0);
    for (std::uint32_t k0 = 0; k0 < v_.size(); ++k0)
      for (int e0 = 0; e0 < 3; ++e0) {
        if (walked_[3 * k0 + e0]) continue;
        face_.clear();
        std::uint32_t at = k0;
        int e = e0;
        do {
          walked_[3 * at + e] = 1;
          face_.push_back(at);
          const std::uint32_t next = v_[at].nb[e];
          e = (slotOf(next, at) + 1) % 3;
          at = next;
        } while (at != k0 || e != e0);
        if (face_.size() < 3) continue;
        Vec<3> p0 = Vec<3>::Zero();
        for (const std::uint32_t k : face_) p0 += v_[k].x;
        p0 /= static_cast<double>(face_.size());
        const Tensor<3> p0p0 = p0 * p0.transpose();
        for (std::size_t q = 0; q < face_.size(); ++q) {
          const Vec<3>& a = v_[face_[q]].x;
          const Vec<3>& b = v_[face_[(q + 1) % face_.size()]].x;
          const double V6 = std::abs(p0.dot(a.cross(b)));
          const Vec<3> s = p0 + a + b;
          sixVolume += V6;
          m1 += (V6 / 24.0) * s;
          m2 += (V6 / 120.0) * (p0p0 + a * a.transpose() + b * b.transpose() + s * s.transpose());
        }
      }
    return cellMoments<3>(sixVolume / 6.0, m1, m2);
  }

private:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  struct Corner {
    Vec<3> x;
    std::array<std::uint32_t, 3> nb; // counterclockwise seen from outside
  };
  int slotOf(std::uint32_t k, std::uint32_t u) const {
    const auto& nb = v_[k].nb;
    return nb[0] == u ? 0 : (nb[1] == u ? 1 : 2);
  }

  std::vector<Corner> v_;
  std::vector<double> dist_;                 // scratch: signed distances to the plane
  std::vector<std::uint32_t> remap_;         // scratch: old corner -> new
  mutable std::vector<std::uint8_t> walked_; // scratch: directed edges walked
  mutable std::vector<std::uint32_t> face_;  // scratch: one face's corners
  double a_ = 0.0, r2Max_ = 0.0;
};

// The cell of the particle at the origin among neighbors at offsets d[k] (a neighbor's position
// minus the particle's) and their mirror images -d[k]: K n -K for the Voronoi cell K, the part
// of K symmetric about the particle. Why the mirrors: at a free surface no neighbor bounds K on
// the outside, and K alone jumps between reaching the starting box (open) and ending at the
// bisector of a neighbor that has moved a hair outwards, far out (closed, and long): the ASPH
// ellipses of a Taylor bar's side flipped between round and the aspect limit from step to step.
// K n -K is bounded wherever some neighbor lies on one side or the other, and continuous in the
// positions; where K is already symmetric (a lattice's interior) it is K, and a lattice's face,
// edge and corner particles get the interior's cell. The same offsets in the same order give the
// same bits. The cell starts as the box |x_k| <= halfWidth. Returns
// false where the cell stays open (no neighbor on either side along some direction: a single
// layer, a lone particle); its moments are then not meaningful.
template <int Dim, class Offsets>
bool voronoiCell(VoronoiCell<Dim>& cell, const Offsets& d, double halfWidth) {
  thread_local std::vector<std::pair<double, std::uint32_t>> order; // (|d|^2, k) that can cut
  thread_local std::vector<std::uint32_t> cut;                      // k that cut K
  cell.reset(halfWidth);
  order.clear();
  double r2Min = std::numeric_limits<double>::infinity();
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(d.size()); ++k) {
    const double r2 = d[k].squaredNorm();
    if (r2 > 0.0 && r2 < 4.0 * cell.farthestCorner2())
      order.push_back({r2, k}), r2Min = std::min(r2Min, r2);
  }
  // K: the nearest shell first (within sqrt 2.5 of the nearest: a lattice's face and edge
  // neighbors, which make its cell), then the rest that can still cut (nearer than twice the
  // farthest corner), each pass in the offsets' order. No sort: the cell does not depend on the
  // order, and its bits depend on the offsets' order only. The neighbors that cut are kept:
  // K's faces are among them.
  cut.clear();
  for (const auto& [r2, k] : order)
    if (r2 < 2.5 * r2Min && cell.clipByNeighbor(d[k])) cut.push_back(k);
  for (const auto& [r2, k] : order)
    if (r2 >= 2.5 * r2Min && r2 < 4.0 * cell.farthestCorner2() && cell.clipByNeighbor(d[k]))
      cut.push_back(k);
  // K n -K: K cut by those neighbors mirrored through the particle.
  for (const std::uint32_t k : cut)
    if (d[k].squaredNorm() < 4.0 * cell.farthestCorner2()) cell.clipByNeighbor(-d[k]);
  return !cell.open();
}

} // namespace spall::solvers
