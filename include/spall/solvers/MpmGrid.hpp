#pragma once
// The material point method's background grid and its transfers (Sulsky, Chen & Schreyer 1994;
// the modified update-stress-last order of Sulsky, Zhou & Schreyer 1995 and Nairn 2003):
//
//   P2G   m_I = sum_p S_Ip m_p,  (mv)_I = sum_p S_Ip m_p v_p,  f_I = -sum_p V_p sigma_p grad S_Ip
//   grid  v_I = (mv)_I / m_I,  v^L_I = v_I + dt f_I / m_I  (walls: no normal component)
//   G2P   v_p <- flip (v_p + sum S_Ip (v^L_I - v_I)) + (1 - flip) sum S_Ip v^L_I,
//         x_p <- x_p + dt sum S_Ip v^L_I
//   remap v_I = sum_p S_Ip m_p v_p / m_I  (the new particle velocities: MUSL)
//   L_p = sum_I v_I (x) grad S_Ip, which the material update takes for dt.
//
// The grid is an unbounded lattice X = origin + k hc: only nodes some particle touches exist
// (numbered afresh each step), so material can go anywhere. Every node sum runs over its
// particles in the order the caller gives (particle id): a node's value is then the same on any
// rank that holds all of its particles, whatever else the rank holds, which keeps a run's result
// independent of the rank count. Physics only: no MPI (methods/MpmMethod sends the ghosts).
#include "spall/core/Types.hpp"
#include "spall/solvers/Config.hpp"
#include "spall/solvers/MpmShapes.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace spall::solvers {

// A rigid wall as a grid constraint: nodes on or behind the plane keep no velocity along its
// normal (a symmetry plane that lets material slide, as SPH's mirror images do).
template <int Dim> struct GridWall {
  Vec<Dim> point, normal; // normal (unit) points into the material
};

// What the transfers read and write of the particles: rows [0, rows) of the store (owned first,
// then ghosts), of which the first `owned` are this rank's.
template <int Dim> struct MpmParticles {
  std::span<Vec<Dim>> x, v, a;
  std::span<const double> m, rho, p, halfWidth;
  std::span<const Tensor<3>> S; // deviatoric stress; empty for fluids
  std::size_t owned = 0;
};

template <int Dim> class MpmGrid {
public:
  virtual ~MpmGrid() = default;
  // The step's transfers up to the new particle velocities and positions (owned rows), with the
  // particles' nodes from their positions now; `order` lists every row, in id order.
  virtual void project(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order,
                       double dt) = 0;
  // After the ghosts received their new velocities: the grid velocity from the new particle
  // momenta on the same nodes and weights (MUSL), and each owned row's velocity gradient (the
  // Dim x Dim block of L; the rest zero).
  virtual void velocityGradient(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order,
                                std::span<Tensor<3>> L) = 0;
  // Nodes touched, for the statistics (the last project()).
  virtual std::size_t nodes() const = 0;
  // How far (per axis, m) a particle of half-width lp reaches its nodes' other particles: what
  // the halo must bring so that every node an owned particle touches is complete.
  virtual double haloReach(double lpMax) const = 0;
};

// axisymmetric (rz, Dim 2): x = r, the points are rings (mass and volume 2 pi r times their
// area's), the hoop stress adds sigma_tt S / r to the radial force and v_r / r is L_tt (Sulsky &
// Schreyer 1996).
template <int Dim>
std::unique_ptr<MpmGrid<Dim>> makeMpmGrid(const MpmConfig& config, const Vec<Dim>& origin,
                                          std::vector<GridWall<Dim>> walls,
                                          bool axisymmetric = false);

} // namespace spall::solvers
