#pragma once
// What the solvers and boundaries are configured with. The deck reader (io/Deck) parses into
// these; the solvers know nothing of TOML.
#include "spall/core/Error.hpp"
#include "spall/core/NameTable.hpp"

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace spall {

enum class KernelType { CubicSpline, WendlandC2, WendlandC4 };
inline constexpr NameTable<KernelType, 3> kKernelNames{{{{KernelType::CubicSpline, "cubic_spline"},
                                                         {KernelType::WendlandC2, "wendland_c2"},
                                                         {KernelType::WendlandC4, "wendland_c4"}}}};
enum class DensityMethod {
  Continuity,         // d rho/dt = sum_j m_j (v_i - v_j) . grad W_ij
  Summation,          // rho_i = sum_j m_j W_ij   (Lam et al. 2001, Eq. 18)
  NormalizedSummation // rho_i = sum m_j W_ij / sum (m_j/rho_j) W_ij  (Lam et al. 2001, Eq. 25)
};
inline constexpr NameTable<DensityMethod, 3> kDensityNames{
    {{{DensityMethod::Continuity, "continuity"},
      {DensityMethod::Summation, "summation"},
      {DensityMethod::NormalizedSummation, "normalized_summation"}}}};

// The pair term of the momentum and energy equations. Both conserve momentum and energy exactly.
enum class StressForm {
  RhoSquared, // sigma_i/rho_i^2 + sigma_j/rho_j^2  (Lam et al. 2001, Eqs. 20-21)
  RhoProduct  // (sigma_i + sigma_j)/(rho_i rho_j): stable at interfaces of very unequal density
};
inline constexpr NameTable<StressForm, 2> kStressFormNames{
    {{{StressForm::RhoSquared, "rho_squared"}, {StressForm::RhoProduct, "rho_product"}}}};

// reconstruct: the pair's approach speed is taken from the velocities reconstructed linearly to
// the pair's midpoint with each particle's velocity gradient L, limited by van Leer's limiter
// (Frontiere, Raskin & Owen 2017, CRKSPH, Sec. 2.4; Rosswog 2015): zero for any linear velocity
// field (uniform compression, shear, plastic flow), the full viscosity across a shock, where the
// two gradients disagree. Solids only (it reads the velocity gradient strength already computes);
// on by default for them (the deck reader decides; decks/README.md).
struct ArtificialViscosityConfig {
  double alpha = 1.0;
  double beta = 2.0;
  bool balsara = false;
  bool reconstruct = false;
  bool reconstructGiven = false; // the deck sets artificial_viscosity.reconstruction
  SourceLocation balsaraWhere;   // for the warning on a loaded body at rest (io/DeckDetail.cpp)
};

// Monaghan's artificial stress against the tensile instability (Gray, Monaghan & Swift 2001):
// R = -epsilon sigma'/rho^2 on the tensile principal stresses, weighted by f_ij^exponent with
// f_ij = W(r_ij)/W(dp) in the pair term.
// On by default where a material has strength (the deck reader decides; decks/README.md).
struct ArtificialStressConfig {
  bool enabled = false;
  bool given = false; // the deck has a [solver.artificial_stress] table
  double epsilon = 0.3;
  int exponent = 4;
};

// The kernel gradient of the solid path: the velocity gradient, the density rate and each
// particle's own stress in the momentum and energy equations.
enum class VelocityGradient {
  Sph,      // grad_i W_ij; L_i = -sum_j (m_j/rho_j) v_ij (x) grad_i W_ij
  Corrected // B_i grad_i W_ij with B_i = M_i^-T, M_i = -sum_j (m_j/rho_j) x_ij (x) grad_i W_ij:
            // exact for linear fields, at free surfaces too (Randles & Libersky 1996; Bonet & Lok
            // 1999)
};
inline constexpr NameTable<VelocityGradient, 2> kVelocityGradientNames{
    {{{VelocityGradient::Sph, "sph"}, {VelocityGradient::Corrected, "corrected"}}}};

// run.geometry. RZ: axisymmetric in the r-z half-plane (dimension 2, x = r >= 0, y = z); a
// particle is a ring, its mass m the ring's (2 pi r times its area times rho). The planar loops
// run with the area mass m/(2 pi r), the axis is a mirror (images at -r), and the hoop terms
// are added per particle (solvers/Axisymmetric.hpp).
enum class Geometry { Cartesian, RZ };
inline constexpr NameTable<Geometry, 2> kGeometryNames{
    {{{Geometry::Cartesian, "cartesian"}, {Geometry::RZ, "rz"}}}};

// How particles of different bodies interact.
enum class Contact {
  Welded,       // like one continuum: bodies touching under tension stick
  Frictionless, // only compression across a body boundary: bodies slide and separate freely
  Auto,         // welded where bodies touch at t = 0 (a bonded assembly), frictionless between
                // bodies that meet later (impacts)
  Friction      // MPM: as Frictionless, and Coulomb friction where the bodies slide
};
inline constexpr NameTable<Contact, 4> kContactNames{{{{Contact::Auto, "auto"},
                                                       {Contact::Welded, "welded"},
                                                       {Contact::Frictionless, "frictionless"},
                                                       {Contact::Friction, "friction"}}}};
// MPM gives each body its own velocity field on the grid with these (one field otherwise).
constexpr bool fieldPerBody(Contact c) {
  return c == Contact::Frictionless || c == Contact::Friction;
}

// The material point method's grid and transfers ([solver.mpm]).
enum class MpmShape {
  Linear, // tent functions of the nodes (Sulsky, Chen & Schreyer 1994)
  Gimp,   // uGIMP: the tent convolved with the particle's box of half-width l_p, the box as
          // made (Bardenhagen & Kober 2004, Eq. 37)
  CpGimp, // GIMP whose box follows the motion (contiguous-particle GIMP, Wallstedt & Guilkey
          // 2008): its half-widths the deformed domain's along the axes, at most half a cell
          // (MpmShapes.hpp, gimpBox)
  Cpdi    // CPDI1: the tent averaged over the particle's deformed domain, a parallelogram
          // (parallelepiped) that follows F (Sadeghirad, Brannon & Burghardt 2011)
};
inline constexpr NameTable<MpmShape, 4> kMpmShapeNames{{{{MpmShape::Linear, "linear"},
                                                         {MpmShape::Gimp, "gimp"},
                                                         {MpmShape::CpGimp, "cpgimp"},
                                                         {MpmShape::Cpdi, "cpdi"}}}};
// How the grid's velocities return to the points (MpmGrid.hpp).
enum class MpmTransfer {
  Flip, // the grid's velocity change (FLIP), blended with its velocity (PIC) by `flip`
  Apic  // the grid's velocity and its gradient, an affine field per point (Jiang et al. 2015)
};
inline constexpr NameTable<MpmTransfer, 2> kMpmTransferNames{
    {{{MpmTransfer::Flip, "flip"}, {MpmTransfer::Apic, "apic"}}}};
// solver.method: smoothed particles, adaptive (ellipsoidal) ones, or the material point method.
enum class SolverMethod { Sph, Asph, Mpm };
inline constexpr NameTable<SolverMethod, 3> kSolverMethodNames{
    {{{SolverMethod::Sph, "sph"}, {SolverMethod::Asph, "asph"}, {SolverMethod::Mpm, "mpm"}}}};

struct MpmConfig {
  double cell_size = 0.0; // m; 0: twice the finest body spacing (io/Deck resolves it)
  MpmShape shape = MpmShape::CpGimp;
  MpmTransfer transfer = MpmTransfer::Flip;
  double flip = 1.0; // Flip: 1 is FLIP's velocity update, 0 PIC's, between the blend
  // The bulk viscosity q = rho (C_Q (l tr D)^2 - C_L l c tr D) in compression (tr D < 0), l the
  // cell size (von Neumann & Richtmyer 1950; Landshoff's linear term): 0, 0 is none.
  double viscosity_linear = 0.0, viscosity_quadratic = 0.0;
  // Coulomb's coefficient between the bodies' velocity fields (contact = "friction"): where
  // they meet, the tangential velocity changes by at most friction times the normal change.
  double friction = 0.0;
  bool viscous() const { return viscosity_linear > 0.0 || viscosity_quadratic > 0.0; }
  SourceLocation where; // the [solver.mpm] table (or [solver])
};

struct SolverConfig {
  SolverMethod method = SolverMethod::Sph;
  KernelType kernel = KernelType::CubicSpline;
  double nodes_per_h = 1.5; // n_h target (Owen 2010, Sec. II-A)
  double cfl = 0.25;
  DensityMethod density = DensityMethod::Continuity;
  StressForm stress_form = StressForm::RhoProduct;
  ArtificialViscosityConfig artificial_viscosity;
  ArtificialStressConfig artificial_stress;
  VelocityGradient velocity_gradient = VelocityGradient::Sph;
  bool velocityGradientGiven = false; // the deck sets velocity_gradient (else: io/Deck.cpp)
  Contact contact = Contact::Welded;  // a deck's default is Auto (io/keys/SolverKeys.cpp)
  // Limits on the smoothing scale: absolute bounds [h_min, h_max] in m (0 / inf: none), and
  // bounds relative to the particle's own volume, h_min_ratio <= h / (n_h (m/rho)^(1/dim)) <=
  // h_max_ratio. The upper one stops h from growing without end at free surfaces, where the
  // neighbor count is one-sided; the lower one stops it from shrinking without end where
  // particles pile up closer than their own volumes allow (stress-free debris of eroded
  // particles: h fell to a tenth of the spacing and the time step with it).
  double h_min = 0.0;
  double h_max = std::numeric_limits<double>::infinity();
  double h_min_ratio = 0.5;
  double h_max_ratio = 2.0;
  // ASPH: the longest axis of the smoothing ellipsoid is at most this many times the shortest.
  double max_aspect_ratio = 10.0;
  // ASPH: each particle's Voronoi cell, which gives its ellipse the shape it relaxes towards,
  // is cut again every this many steps (staggered over the particles by id), and kept between.
  int shape_interval = 4;
  // Neighbor lists kept across steps: searched with supports this fraction wider, searched again
  // when the particles' travel or their supports' growth has used it up (neighbors/VerletList).
  // The results are the same for any value; 0 searches every step.
  double neighbor_skin = 0.1;
  // Hierarchical time steps (methods/TimeBins.hpp): particles step in power-of-two bins of the
  // finest step, dt_min 2^k with k < time_bins, each by its own stable step; 1: one step for all.
  int time_bins = 1;
  Geometry geometry = Geometry::Cartesian; // from run.geometry
  MpmConfig mpm;                           // solver.method = "mpm"
  std::vector<std::string> sphOnlyKeys;    // given with "mpm", where they do nothing
  std::vector<std::string> asphOnlyKeys;   // given with "sph", where they do nothing
  SourceLocation where;
};

enum class BoundaryType { RigidWall, Periodic, Pressure };
inline constexpr NameTable<BoundaryType, 3> kBoundaryTypeNames{
    {{{BoundaryType::RigidWall, "rigid_wall"},
      {BoundaryType::Periodic, "periodic"},
      {BoundaryType::Pressure, "pressure"}}}};

struct BoundaryConfig {
  BoundaryType type = BoundaryType::RigidWall;
  std::vector<double> point, normal; // rigid_wall (normal points into the material)
  // rigid_wall: a particle found behind the plane is folded back (position and velocity
  // mirrored). The rz axis is such a mirror: a ring cannot have r < 0.
  bool fold = false;
  double friction = 0.0;       // rigid_wall, MPM: Coulomb's coefficient; 0 slips
  int axis = 0;                // periodic: 0 = x, 1 = y, 2 = z
  double min = 0.0, max = 0.0; // periodic
  // pressure: the body it loads (name and index in the deck) and its (time, Pa) table, linear
  // between rows, the first value before the first row and the last after the last.
  std::string body;
  std::int32_t bodyIndex = -1;
  std::vector<std::pair<double, double>> pressure;
  SourceLocation where;
};

} // namespace spall
