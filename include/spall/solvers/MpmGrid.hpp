#pragma once
// The material point method's background grid and its transfers (Sulsky, Chen & Schreyer 1994;
// the modified update-stress-last order of Sulsky, Zhou & Schreyer 1995 and Nairn 2003):
//
//   P2G   m_I = sum_p S_Ip m_p,  (mv)_I = sum_p S_Ip m_p v_p,  f_I = -sum_p V_p sigma_p grad S_Ip
//   grid  v_I = (mv)_I / m_I,  v^L_I = v_I + dt f_I / m_I  (walls: no normal component;
//         external forces sum_p S_Ip m_p a_p,ext in f_I; a fixed body's nodes its velocity)
//   G2P   v_p <- flip (v_p + sum S_Ip (v^L_I - v_I)) + (1 - flip) sum S_Ip v^L_I,
//         x_p <- x_p + dt sum S_Ip v^L_I
//         APIC (transfer = "apic"; Jiang, Schroeder, Selle, Teran & Stomakhin 2015): each point
//         carries the affine field v_p + C_p (x - x_p); P2G's momentum is
//         sum_p S_Ip m_p (v_p + C_p (x_I - x_p)), and G2P sets v_p <- sum S_Ip v^L_I and
//         C_p <- sum v^L_I (x) grad S_Ip (Jiang et al.'s B_p D_p^-1 for the tent; the same
//         gradient for GIMP and CPDI). An affine grid velocity returns exactly (the weights are
//         linearly complete): no PIC smearing of a stretch or a spin, while the modes the grid
//         cannot carry (FLIP's ringing) are filtered as PIC filters them. Momentum is conserved;
//         angular momentum only as closely as the gradient stands in for B_p D_p^-1.
//   remap v_I = sum_p S_Ip m_p v_p / m_I  (the new particle velocities: MUSL; APIC's with the
//         affine part about the points' places at the step's start)
//   L_p = sum_I v_I (x) grad S_Ip, which the material update takes for dt.
//
// The grid is an unbounded lattice X = origin + k hc: only nodes some particle touches exist
// (numbered afresh each step), so material can go anywhere. Every node sum runs over its
// particles in the order the caller gives (particle id): a node's value is then the same on any
// rank that holds all of its particles, whatever else the rank holds, which keeps a run's result
// independent of the rank count. Physics only: no MPI (methods/MpmMethod sends the ghosts).
//
// Contact (Bardenhagen, Brackbill & Sulsky 2000, frictionless): with one velocity field the grid
// makes bodies that share nodes move as one (no slip, Sulsky's original). With a field per
// particle (contact groups), every node carries a mass, momentum and force per field present, and
// where several meet, a field moving toward the others is stopped along the interface's normal:
// with v_cm the node's centre-of-mass velocity and n_b the field's outward normal (from the
// fields' g = sum_p V_p grad S_Ip, which points out of a field's material at its surface, in rz
// with the points' areas V_p / r_p in the r-z plane: n_b ~ g_b - sum_{c != b} g_c),
//   (v_b - v_cm) . n_b > 0  =>  v_b <- v_b - ((v_b - v_cm) . n_b) n_b,
// where the fields' material fills the node's support (a gap is not a contact: MpmGridContact.hpp),
// applied to the grid velocities before the force, after it (the force acting on the corrected
// velocity) and after the remap; the first two reach the particles' velocities (the bodies'
// momentum exchange), and on a wall plane n_b lies in the plane. Frictionless, the tangential
// part is untouched; with Coulomb friction mu (contact = "friction"), with u_t = the tangential
// part of v_b - v_cm, v_b <- v_b - min(mu (v_b - v_cm) . n_b, |u_t|) u_t / |u_t| (it sticks
// where mu times the approach exceeds the slide), and friction's work (the impulse times the
// slide it acts across) heats the field's points by their shares of its mass. Fields moving
// apart are free (no tension). A wall with friction takes from a node on it up to mu times what
// the step's force pressed on it of its slide, booked alike. With two fields the
// normals are opposite and the corrections conserve momentum exactly; with more, the node's
// momentum to the normals' spread.
#include "spall/core/MemoryAccounting.hpp"
#include "spall/core/Types.hpp"
#include "spall/solvers/Config.hpp"
#include "spall/solvers/GridNodes.hpp"
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
  double friction = 0.0;  // Coulomb's coefficient against what the force presses on it
};

// What the transfers read and write of the particles: rows [0, rows) of the store (owned first,
// then ghosts), of which the first `owned` are this rank's.
template <int Dim> struct MpmParticles {
  std::span<Vec<Dim>> x, v, a;
  std::span<const double> m, rho, p, halfWidth;
  std::span<const Tensor<3>> S;  // deviatoric stress; empty for fluids
  std::span<Tensor<Dim>> domain; // CPDI: each row's half-edge vectors (columns)
  std::span<const double> q;     // each row's bulk viscosity (a pressure); empty: none
  std::span<Tensor<Dim>> affine; // APIC: each row's velocity gradient C_p; empty: FLIP
  std::size_t owned = 0;
  std::span<const std::int32_t> field; // each row's velocity field (contact group); empty: one
  // Friction (contact = "friction", walls with friction): project() leaves on each owned row the
  // specific heat (J/kg) its share of the friction's work gave it this step; empty: not asked.
  std::span<double> heat;
  // Loads and supports (methods/MpmMethod fills them from the modules' hooks); empty: none.
  std::span<const Vec<Dim>> aExt;      // each row's external acceleration (damping)
  std::span<const std::uint8_t> rigid; // 1: a fixed body's point, its velocity prescribed
  // The confining pressure P on each row's body. The stress at every node a loaded point
  // touches is shifted by P I for all of its points (the largest P there), as SPH's force loop
  // does (methods/modules/ConfiningPressure.hpp): a uniform stress exerts no force, so the shift
  // acts where the node's support is cut, as the traction -P n dA, and nowhere where another
  // body, a wall or the axis fills it. project() leaves on each owned row the P it felt and its
  // share of the loaded area (loadArea, outward, m^2: the load on it is -P loadArea).
  std::span<double> load;
  std::span<Vec<Dim>> loadArea;
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
  // The grid of the state now, for a snapshot: P2G's sums (mass, momentum, the stress's force)
  // on every node an owned row touches, of which this rank keeps the nodes whose first row in
  // `order` with a weight there is owned: each node once over all ranks, summed as every rank
  // holding its rows sums it. Replaces the last step's grid (the next project() makes its own).
  virtual GridNodes<Dim> snapshot(const MpmParticles<Dim>& P,
                                  std::span<const std::uint32_t> order) = 0;
  // Lattice nodes touched, for the statistics (the last project()).
  virtual std::size_t nodes() const = 0;
  // The bytes its nodes and the points' entries hold allocated (summary.json's memory parts).
  virtual std::size_t bytes() const = 0;
  // How far (per axis, m) a particle reaches its nodes' other particles, when no point's
  // weights reach further than `extent` from it beyond a cell (GIMP: its half-width l_p; CPDI:
  // its domain's half-extent along the axis, sum_i |r_i,a|): what the halo must bring so that
  // every node an owned particle touches is complete.
  virtual double haloReach(double extent) const = 0;
};

// axisymmetric (rz, Dim 2): x = r, the points are rings (mass and volume 2 pi r times their
// area's), the hoop stress adds sigma_tt S / r to the radial force and v_r / r is L_tt (Sulsky &
// Schreyer 1996).
template <int Dim>
std::unique_ptr<MpmGrid<Dim>> makeMpmGrid(const MpmConfig& config, const Vec<Dim>& origin,
                                          std::vector<GridWall<Dim>> walls,
                                          bool axisymmetric = false);

} // namespace spall::solvers
