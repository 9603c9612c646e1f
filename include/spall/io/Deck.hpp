#pragma once
// The typed, validated form of a TOML deck (INTERFACE.md, "Deck schema"). Every value that came
// from the deck keeps the position it came from, so later checks (a body with zero particles,
// overlapping bodies) still report FILE:LINE:COLUMN.
#include "spall/core/Error.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace spall {

struct RunConfig {
  std::string title;
  int dimension = 0;
  double end_time = 0.0;
  std::int64_t max_steps = std::numeric_limits<std::int64_t>::max();
  double resolution = 1.0;
  std::uint64_t seed = 1;
};

enum class KernelType { CubicSpline, WendlandC2, WendlandC4 };
enum class DensityMethod {
  Continuity,         // d rho/dt = sum_j m_j (v_i - v_j) . grad W_ij
  Summation,          // rho_i = sum_j m_j W_ij   (Lam et al. 2001, Eq. 18)
  NormalizedSummation // rho_i = sum m_j W_ij / sum (m_j/rho_j) W_ij  (Lam et al. 2001, Eq. 25)
};

// The pair term of the momentum and energy equations. Both conserve momentum and energy exactly.
enum class StressForm {
  RhoSquared, // sigma_i/rho_i^2 + sigma_j/rho_j^2  (Lam et al. 2001, Eqs. 20-21)
  RhoProduct  // (sigma_i + sigma_j)/(rho_i rho_j): stable at interfaces of very unequal density
};

struct ArtificialViscosityConfig {
  double alpha = 1.0;
  double beta = 2.0;
  bool balsara = false;
};

// Monaghan's artificial stress against the tensile instability (Gray, Monaghan & Swift 2001):
// R = -epsilon sigma'/rho^2 on the tensile principal stresses, weighted by f_ij^exponent with
// f_ij = W(r_ij)/W(dp) in the pair term.
struct ArtificialStressConfig {
  bool enabled = false;
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

// How particles of different bodies interact.
enum class Contact {
  Welded,      // like one continuum: bodies touching under tension stick
  Frictionless // only compression across a body boundary: bodies slide and separate freely
};

struct SolverConfig {
  std::string method = "sph"; // "sph" | "asph" (later "mpm")
  KernelType kernel = KernelType::CubicSpline;
  double nodes_per_h = 1.5; // n_h target (Owen 2010, Sec. II-A)
  double cfl = 0.25;
  DensityMethod density = DensityMethod::Continuity;
  StressForm stress_form = StressForm::RhoSquared;
  ArtificialViscosityConfig artificial_viscosity;
  ArtificialStressConfig artificial_stress;
  VelocityGradient velocity_gradient = VelocityGradient::Sph;
  Contact contact = Contact::Welded;
  // Limits on the smoothing scale: absolute bounds [h_min, h_max] in m (0 / inf: none), and a
  // bound relative to the particle's own volume: h <= h_max_ratio * n_h * (m/rho)^(1/dim), which
  // stops h from growing without end at free surfaces, where the neighbor count is one-sided.
  double h_min = 0.0;
  double h_max = std::numeric_limits<double>::infinity();
  double h_max_ratio = 2.0;
  // ASPH: the longest axis of the smoothing ellipsoid is at most this many times the shortest.
  double max_aspect_ratio = 10.0;
  SourceLocation where;
};

struct DecompositionConfig {
  std::string curve = "hilbert";   // "hilbert" | "morton"
  std::string partitioner = "sfc"; // "sfc" | "metis"
  int rebalance_every = 20;
  double imbalance_threshold = 1.1; // max/mean cost that triggers a rebalance at any step
  bool reproducible = true;         // neighbor sums in a rank-count-independent order
};

struct EosConfig {
  std::string type;                       // "ideal_gas" | "linear" | "mie_gruneisen" | "tillotson"
  double gamma = 0.0;                     // ideal_gas
  double bulk_modulus = 0.0;              // linear
  double c0 = 0.0, s = 0.0, gamma0 = 0.0; // mie_gruneisen (Lam et al. 2001, Eqs. 4-6)
  // tillotson (Tillotson 1962; materials/Eos.hpp)
  double a = 0.0, b = 0.0, A = 0.0, B = 0.0, alpha = 0.0, beta = 0.0;
  double e0 = 0.0, e_iv = 0.0, e_cv = 0.0;
  SourceLocation where;
};

// strength = {type = ...} (INTERFACE.md; materials/Strength.hpp for the models).
struct StrengthConfig {
  std::string type = "none"; // "none" | "elastic" | "von_mises" | "johnson_cook"
  double shear_modulus = 0.0, yield_stress = 0.0;
  // johnson_cook
  double A = 0.0, B = 0.0, n = 1.0, C = 0.0, m = 1.0, reference_strain_rate = 1.0;
  double room_temperature = 293.0, melt_temperature = 0.0, specific_heat = 0.0;
  double taylor_quinney = 0.9;
  SourceLocation where;
};

struct MaterialConfig {
  std::string name;
  double density = 0.0; // reference density rho0
  EosConfig eos;
  StrengthConfig strength;
  SourceLocation where;
};

struct ShapeConfig {
  std::string type;                              // "box" | "sphere" | "cylinder" | "ring"
  std::vector<double> min, max;                  // box
  std::vector<double> center;                    // sphere, ring
  double radius = 0.0;                           // sphere, cylinder
  std::vector<double> base, axis;                // cylinder (3D)
  double length = 0.0;                           // cylinder
  double inner_radius = 0.0, outer_radius = 0.0; // ring (2D)
  SourceLocation where;
};

struct LinearVelocityConfig {
  std::vector<double> center;
  std::vector<std::vector<double>> gradient; // G: v += G (x - center), dimension x dimension
};

struct RadialVelocityConfig {
  std::vector<double> center;
  double speed = 0.0; // added along (x - center)/|x - center|; negative: inflow (Noh)
};

// The first bending mode of a beam clamped at `root` and lying along +x, as a transverse (y)
// velocity: v_y(x) = tip_speed * F(x - root_x) / F(length), zero for x < root_x (the clamp).
struct CantileverVelocityConfig {
  std::vector<double> root;
  double length = 0.0;
  double tip_speed = 0.0;
};

struct BodyConfig {
  std::string name;
  std::string material;    // name as in the deck
  int material_index = -1; // resolved index into Deck::materials
  ShapeConfig shape;
  double spacing = 0.0;          // before run.resolution
  std::string lattice = "cubic"; // "cubic" | "hexagonal"
  std::vector<double> velocity;  // dimension entries
  std::optional<double> initial_density;
  std::optional<double> initial_specific_energy;
  std::optional<double> initial_pressure;
  double jitter = 0.0; // fraction of the spacing
  std::optional<RadialVelocityConfig> radial_velocity;
  double insert_time = 0.0;
  std::optional<std::vector<std::vector<double>>> lattice_transform; // dimension x dimension
  bool allow_overlap = false; // may overlap bodies listed before it
  std::optional<CantileverVelocityConfig> cantilever_velocity;
  std::optional<LinearVelocityConfig> linear_velocity;
  bool fixed = false; // held in place: v = 0, a = 0 (a clamp); still carries stress
  SourceLocation where;
};

struct EnergySourceConfig {
  std::vector<double> center;
  double radius = 0.0;
  double energy = 0.0; // J
  SourceLocation where;
};

struct BoundaryConfig {
  std::string type;                  // "rigid_wall" | "periodic"
  std::vector<double> point, normal; // rigid_wall (normal points into the material)
  int axis = 0;                      // periodic: 0 = x, 1 = y, 2 = z
  double min = 0.0, max = 0.0;       // periodic
  SourceLocation where;
};

struct OutputConfig {
  std::string directory;
  double every = 0.0;              // s of simulated time between snapshots (0: not by time)
  std::int64_t every_steps = 0;    // steps between snapshots (0: not by steps)
  std::vector<std::string> fields; // empty: all present
  std::int64_t history_every_steps = 1;
  SourceLocation where;
};

struct CheckpointConfig {
  std::int64_t every_steps = 0;
  double every_wall_seconds = 0.0;
  int keep = 2;
  SourceLocation where;
};

struct ProbeConfig {
  std::string name;
  std::vector<double> position;
  std::string track = "material"; // "material" | "space"
  std::vector<std::string> fields;
  SourceLocation where;
};

struct Deck {
  std::string path;          // the deck file as given
  std::string resolved_toml; // the deck with overrides applied, as TOML text
  RunConfig run;
  SolverConfig solver;
  DecompositionConfig decomposition;
  std::vector<MaterialConfig> materials;
  std::vector<BodyConfig> bodies;
  std::vector<EnergySourceConfig> energy_sources;
  std::vector<BoundaryConfig> boundaries;
  OutputConfig output;
  std::optional<CheckpointConfig> checkpoint;
  std::vector<ProbeConfig> probes;
};

// Reads, applies `--set KEY=VALUE` overrides to, and validates a deck. Throws DeckError with the
// position of the first offending value. Writes nothing.
Deck loadDeck(const std::string& path, const std::vector<std::string>& overrides = {});

// What differs between two resolved decks in the keys that shape the physics, one line per key
// ("solver.cfl: 0.3 before, 0.25 now"). A restart may change only run.end_time, run.max_steps,
// run.title and the [output], [checkpoint] and [decomposition] tables; everything else must be
// as the checkpoint was written. Array-of-tables entries are matched by their `name`.
std::vector<std::string> deckPhysicsDifferences(const std::string& before, const std::string& now);

} // namespace spall
