#pragma once
// The grid's velocity fields with contact (MpmGrid.hpp, "Contact"): each node's fields as a
// list in ascending field, and the correction where they meet (frictionless or Coulomb's).
#include "MpmGridImpl.hpp"
#include "MpmGridWalls.hpp"

#include <numbers>

namespace spall::solvers::grid {

// Contact acts at a node whose support this fraction of material fills (contact()).
constexpr double kCovered = 0.9;

// With contact: each entry's node becomes its (node, field) pair's number. A node's fields
// form a list in ascending field, so the contact sums over them run in the same order on
// every rank.
template <int Dim, MpmShape Shape>
void Grid<Dim, Shape>::numberFields(const MpmParticles<Dim>& P, std::size_t rows) {
  head_.assign(key_.size(), kNone);
  site_.clear();
  fieldOf_.clear();
  next_.clear();
  for (std::size_t r = 0; r < rows; ++r) {
    const std::int32_t b = P.field[r];
    for (std::size_t e = from(r); e < to(r); ++e) {
      std::uint32_t& I = node_[e];
      // Walk the node's list to the first pair of field >= b (by index: next_ grows below).
      std::uint32_t before = kNone, at = head_[I];
      while (at != kNone && fieldOf_[at] < b) before = at, at = next_[at];
      if (at == kNone || fieldOf_[at] != b) {
        const auto fresh = static_cast<std::uint32_t>(site_.size());
        site_.push_back(I);
        fieldOf_.push_back(b);
        next_.push_back(at);
        (before == kNone ? head_[I] : next_[before]) = fresh;
        at = fresh;
      }
      I = at;
    }
  }
}

// Contact at every node where fields meet (MpmGrid.hpp): a field moving toward the node's
// centre of mass along its outward normal loses that part of its velocity, where the fields'
// material covers the node's support (sum_p S_Ip V_p >= kCovered of its volume). Without that
// check the fields meet one to two cells before their surfaces do (their supports overlap
// across the gap), and the early stop of the surface layers, released as they part, gave the
// colliding disks +6% of energy; with it, +1.7% at most (decks/README).
// With Coulomb friction mu (Bardenhagen, Brackbill & Sulsky 2000), a field sliding relative to
// the centre of mass at u_t also loses min(mu (approach), |u_t|) of it along u_t:
// the tangential impulse at most mu times the normal one, beyond which the field sticks. With
// `heat`, friction's work is added there (J) for the field's points to take up as internal
// energy (frictionWork, MpmGridWalls.hpp): without `start` (the correction of the step's
// starting velocities) the slide at the start is the field's own, so the work is the kinetic
// energy the correction takes; after the force, `start` holds the velocities before it.
template <int Dim, MpmShape Shape>
void Grid<Dim, Shape>::contact(std::vector<Vec<Dim>>& v, std::vector<double>* heat,
                               const std::vector<Vec<Dim>>* start) const {
  const double mu = c_.friction;
  for (std::size_t I = 0; I < key_.size(); ++I) {
    const std::uint32_t first = head_[I];
    if (next_[first] == kNone) continue; // one field: nothing to correct
    double M = 0.0;
    Vec<Dim> mv = Vec<Dim>::Zero(), G = Vec<Dim>::Zero();
    for (std::uint32_t b = first; b != kNone; b = next_[b]) {
      M += mass_[b];
      mv += mass_[b] * v[b];
      G += gradV_[b];
    }
    if (!(M > 0.0)) continue;
    double V = 0.0;
    for (std::uint32_t b = first; b != kNone; b = next_[b]) V += volume_[b];
    if (V < kCovered * capacity(I)) continue; // a gap: the fields only approach
    // A fixed body at the node is the reference (infinite mass) and is not corrected.
    Vec<Dim> vcm = mv / M;
    std::uint32_t held = kNone;
    if (!rigid_.empty())
      for (std::uint32_t b = first; b != kNone && held == kNone; b = next_[b])
        if (rigid_[b]) held = b, vcm = v[b];
    // The reference at the step's start (the same mass weights, or the held field's velocity).
    Vec<Dim> vcm0 = Vec<Dim>::Zero();
    if (heat && start) {
      for (std::uint32_t b = first; b != kNone; b = next_[b]) vcm0 += mass_[b] * (*start)[b];
      vcm0 = held == kNone ? Vec<Dim>(vcm0 / M) : (*start)[held];
    }
    const Vec<Dim> X = place(key_[I]);
    for (std::uint32_t b = first; b != kNone; b = next_[b]) {
      Vec<Dim> n = 2.0 * gradV_[b] - G;
      // On a wall plane (a rigid wall, a symmetry plane, the rz axis) the normal lies in the
      // plane: the wall takes the velocity across it anyway (constrain()), and the volume
      // gradients' parts across it, where a body's edge lies inside the node's support and the
      // other's does not, say nothing of where the fields meet. Along a normal leaning across
      // the plane the correction took only part of the approach, the wall the rest of the
      // correction: on the axis of an rz rod striking a block the two bodies' axial rings
      // passed through each other at 4-5 km/s (decks/topics/mpm.md).
      for (const auto& w : walls_)
        if (onWall(X, w)) n -= n.dot(w.normal) * w.normal;
      const double length = n.norm();
      if (b == held || !(mass_[b] > 0.0) || !(length > 0.0)) continue;
      n /= length;
      const Vec<Dim> u = v[b] - vcm;
      const double approach = u.dot(n);
      if (!(approach > 0.0)) continue;
      v[b] -= approach * n;
      if (!(mu > 0.0)) continue;
      const Vec<Dim> ut = u - approach * n;
      const double slide = ut.norm();
      if (!(slide > 0.0)) continue;
      const double kept = std::max(0.0, 1.0 - mu * approach / slide); // 0: it sticks
      v[b] -= (1.0 - kept) * ut;
      if (!heat) continue;
      // Before the force its own slide is the start's (the kinetic energy taken).
      Vec<Dim> u0 = ut;
      if (start) u0 = (*start)[b] - vcm0, u0 -= u0.dot(n) * n;
      (*heat)[b] += frictionWork<Dim>(mass_[b] * (1.0 - kept) * ut, u0, ut, kept);
    }
  }
}

// A node's support volume, what material filling it maps there: hc^Dim; in rz (rings)
// 2 pi hc^2 r_I, and 2 pi hc^2 hc / 6 on the axis (the tent's moment there); half of it for
// each wall plane the node lies on (no material behind a wall: two bodies sliding along a
// symmetry plane still meet there).
template <int Dim, MpmShape Shape> double Grid<Dim, Shape>::capacity(std::size_t L) const {
  const double hc = c_.cell_size;
  const Vec<Dim> X = place(key_[L]);
  double C = rz_ ? 2.0 * std::numbers::pi * hc * hc * std::max(X[0], hc / 6.0) : std::pow(hc, Dim);
  for (const auto& w : walls_) {
    const bool axis = rz_ && w.normal[0] != 0.0 && std::abs(w.point[0]) <= 1e-9 * hc;
    if (!axis && std::abs((X - w.point).dot(w.normal)) <= 1e-9 * hc) C *= 0.5;
  }
  return C;
}

} // namespace spall::solvers::grid
