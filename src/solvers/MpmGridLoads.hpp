#pragma once
// The grid's pressure loads (MpmParticles::load): each node's load, its force on the fields
// there, and each owned point's share of it; and the supports of fixed bodies.
#include "MpmGridImpl.hpp"

namespace spall::solvers::grid {

// Each lattice node's load: the largest P of the points that weigh on it.
template <int Dim, MpmShape Shape>
void Grid<Dim, Shape>::nodeLoads(const MpmParticles<Dim>& P, std::size_t rows) {
  nodeLoad_.assign(key_.size(), 0.0);
  for (std::size_t r = 0; r < rows; ++r) {
    if (!(P.load[r] > 0.0)) continue;
    for (std::size_t e = from(r); e < to(r); ++e) {
      double& PI = nodeLoad_[lattice(node_[e])];
      if (S_[e] > 0.0) PI = std::max(PI, P.load[r]);
    }
  }
}

// The loads on the nodes: at a lattice node of load P_I and area A_I (a wall's or the rz
// axis's normal part taken by its constraint: no face there), the force -P_I A_I, shared by
// the fields there by mass (one field: all of it). Per field, each field's own area would
// pull bodies in contact apart with the traction P: the node's sum is what cancels where
// another body fills the support.
template <int Dim, MpmShape Shape> void Grid<Dim, Shape>::applyLoads() {
  nodeMass_.assign(key_.size(), 0.0);
  for (std::size_t L = 0; L < key_.size(); ++L) {
    constrainAt(key_[L], area_[L]);
    if (!multi_) {
      nodeMass_[L] = mass_[L];
      continue;
    }
    for (std::uint32_t b = head_[L]; b != kNone; b = next_[b]) nodeMass_[L] += mass_[b];
  }
  for (std::size_t I = 0; I < fields(); ++I) {
    const std::size_t L = lattice(I);
    if (nodeLoad_[L] > 0.0 && nodeMass_[L] > 0.0)
      force_[I] -= (nodeLoad_[L] * mass_[I] / nodeMass_[L]) * area_[L];
  }
}

// The owned rows' share of their nodes' loads, by mass (what the books and the snapshots
// show): F_p = sum_I S_Ip m_p / M_I (-P_I A_I), P_p the largest P_I, loadArea = -F_p / P_p. A
// fixed body's nodes discard their force: no share there.
template <int Dim, MpmShape Shape> void Grid<Dim, Shape>::shareLoads(const MpmParticles<Dim>& P) {
  for (std::size_t r = 0; r < P.owned; ++r) {
    Vec<Dim> F = Vec<Dim>::Zero();
    double Pp = 0.0;
    for (std::size_t e = from(r); e < to(r); ++e) {
      const std::size_t L = lattice(node_[e]);
      const double PI = nodeLoad_[L];
      if (!(PI > 0.0) || !(nodeMass_[L] > 0.0) || !(S_[e] > 0.0)) continue;
      if (!rigid_.empty() && rigid_[node_[e]]) continue;
      F -= (S_[e] * P.m[r] / nodeMass_[L] * PI) * area_[L];
      Pp = std::max(Pp, PI);
    }
    P.load[r] = Pp;
    P.loadArea[r] = Pp > 0.0 ? Vec<Dim>(-F / Pp) : Vec<Dim>::Zero();
  }
}

// The support's impulse at each node a fixed body holds, the momentum the step hands the
// other points there beyond the nodes' forces: J = sum over the node's fields of what G2P
// gives the points that are not fixed (FLIP: (m - m_fix) dv; PIC and APIC: (m - m_fix) v -
// (p - p_fix); blended by flip) minus dt f. The forces of all nodes sum to the external ones
// (the stresses' cancel), so the J add up to the momentum change no force explains: what the
// prescribed velocities and the contact against a held field did. Each held field keeps
// -J / dt by its share of the fixed mass; G2P hands it to the fixed points as the
// acceleration the support cancels (methods/MpmMethod books -m a, as SPH's FixedBodies).
template <int Dim, MpmShape Shape> void Grid<Dim, Shape>::supports(double dt) {
  const double phi = c_.transfer == MpmTransfer::Apic ? 0.0 : c_.flip;
  support_.assign(fields(), Vec<Dim>::Zero());
  const auto fieldsAt = [&](std::size_t L, auto&& each) {
    if (!multi_) return each(static_cast<std::uint32_t>(L));
    for (std::uint32_t b = head_[L]; b != kNone; b = next_[b]) each(b);
  };
  for (std::size_t L = 0; L < key_.size(); ++L) {
    Vec<Dim> J = Vec<Dim>::Zero();
    double held = 0.0;
    fieldsAt(L, [&](std::uint32_t b) {
      const double m = mass_[b] - fixedMass_[b];
      const Vec<Dim> p = momentum_[b] - fixedMomentum_[b];
      J += phi * m * increment_[b] + (1.0 - phi) * (m * velocity_[b] - p) - dt * force_[b];
      if (rigid_[b]) held += fixedMass_[b];
    });
    if (!(held > 0.0)) continue;
    fieldsAt(L, [&](std::uint32_t b) {
      if (rigid_[b]) support_[b] = (-fixedMass_[b] / (held * dt)) * J;
    });
  }
}

} // namespace spall::solvers::grid
