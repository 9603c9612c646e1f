#pragma once
// The typed, validated form of a TOML deck (docs/reference.md, "Deck schema"). Every value that
// came from the deck keeps the position it came from, so later checks (a body with zero particles,
// overlapping bodies) still report FILE:LINE:COLUMN.
#include "spall/core/Error.hpp"
#include "spall/core/NameTable.hpp"
#include "spall/materials/CapPlasticity.hpp"
#include "spall/materials/Damage.hpp"
#include "spall/materials/Eos.hpp"
#include "spall/materials/Erosion.hpp"
#include "spall/materials/Strength.hpp"
#include "spall/solvers/Config.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace spall {

// The deck's numbers: SI (kg, m, s, K, Pa), checked for plausibility (docs/reference.md,
// "Warnings"), or a consistent scaled set (a nondimensional benchmark such as Sulsky's disks),
// where no plausibility warning applies.
enum class Units { SI, Scaled };
inline constexpr NameTable<Units, 2> kUnitNames{{{{Units::SI, "si"}, {Units::Scaled, "scaled"}}}};

struct RunConfig {
  std::string title;
  Units units = Units::SI;
  int dimension = 0;
  Geometry geometry = Geometry::Cartesian; // "rz": axisymmetric (solvers/Config.hpp)
  double end_time = 0.0;
  SourceLocation endTimeWhere; // for the plausibility of end_time against the scene
  std::int64_t max_steps = std::numeric_limits<std::int64_t>::max();
  double resolution = 1.0;
  std::uint64_t seed = 1;
};

enum class CurveType { Hilbert, Morton };
inline constexpr NameTable<CurveType, 2> kCurveNames{
    {{{CurveType::Hilbert, "hilbert"}, {CurveType::Morton, "morton"}}}};
enum class Partitioner { Sfc, Metis };
inline constexpr NameTable<Partitioner, 2> kPartitionerNames{
    {{{Partitioner::Sfc, "sfc"}, {Partitioner::Metis, "metis"}}}};

// What a particle costs the balance: its counted pairs (reproducible), or those weighted by
// the time its rank measured per counted pair (the physics is the same on any partition).
enum class BalanceCost { Counted, Timed };
inline constexpr NameTable<BalanceCost, 2> kBalanceCostNames{
    {{{BalanceCost::Counted, "counted"}, {BalanceCost::Timed, "timed"}}}};

struct DecompositionConfig {
  CurveType curve = CurveType::Hilbert;
  Partitioner partitioner = Partitioner::Sfc;
  BalanceCost cost = BalanceCost::Counted;
  int rebalance_every = 20;
  double imbalance_threshold = 1.1; // max/mean cost that triggers a rebalance at any step
  bool reproducible = true;         // neighbor sums in a rank-count-independent order
};

// A typed table's models as one variant: the alternatives of several variants, in order.
template <class... V> struct VariantCat;
template <class... A, class... B, class... C>
struct VariantCat<std::variant<A...>, std::variant<B...>, std::variant<C...>> {
  using type = std::variant<A..., B..., C...>;
};

// eos = {type = ...}: a model of materials/Eos.hpp, its keys in io/keys/EosKeys.cpp; rho0 is the
// material's density.
struct EosConfig {
  materials::Eos model;
  // The tension limit (Pa, <= 0): the pressure never falls below it (all types but ideal_gas);
  // none by default.
  double min_pressure = -std::numeric_limits<double>::infinity();
  SourceLocation where;
};

// strength = {type = ...}: none (a fluid), a J2 model of materials/Strength.hpp or the cap model
// of materials/CapPlasticity.hpp; their keys in io/keys/StrengthKeys.cpp.
struct NoStrength {};
using StrengthModel = VariantCat<std::variant<NoStrength>, materials::Strength,
                                 std::variant<materials::CapPlasticity>>::type;

struct StrengthConfig {
  StrengthModel model;
  SourceLocation where;

  bool none() const { return std::holds_alternative<NoStrength>(model); }
  const materials::CapPlasticity* cap() const {
    return std::get_if<materials::CapPlasticity>(&model);
  }
  // The models that carry a temperature start at their room temperature, the others at 0.
  bool tracksTemperature() const {
    return std::visit(
        [](const auto& m) {
          return requires {
            m.Troom;
          };
        },
        model);
  }
  double initialTemperature() const {
    return std::visit(
        [](const auto& m) {
          if constexpr (requires { m.Troom; })
            return m.Troom;
          else
            return 0.0;
        },
        model);
  }
  // The J2 models that accumulate an equivalent plastic strain (what Johnson-Cook damage reads).
  bool hasPlasticStrain() const {
    return std::visit(
        [](const auto& m) {
          using T = std::decay_t<decltype(m)>;
          if constexpr (requires { T::accumulatesPlasticStrain; })
            return T::accumulatesPlasticStrain;
          else
            return false;
        },
        model);
  }
};

// damage = {type = ...}: a model of materials/Damage.hpp, its keys in io/keys/DamageKeys.cpp.
struct NoDamage {};
using DamageModel = VariantCat<std::variant<NoDamage>, materials::Damage, std::variant<>>::type;

struct DamageConfig {
  DamageModel model;
  SourceLocation where;
  bool none() const { return std::holds_alternative<NoDamage>(model); }
};

// The names the deck gives the models (from their key tables, io/keys/).
std::string_view eosTypeName(const EosConfig& c);
std::string_view strengthTypeName(const StrengthConfig& c);
std::string_view damageTypeName(const DamageConfig& c);

// porosity = {type = "p_alpha", ...} (docs/reference.md; materials/Porosity.hpp for the model).
enum class PorosityType { None, PAlpha };
inline constexpr NameTable<PorosityType, 2> kPorosityNames{
    {{{PorosityType::None, "none"}, {PorosityType::PAlpha, "p_alpha"}}}};

struct PorosityConfig {
  PorosityType type = PorosityType::None;
  double alpha0 = 1.0, elastic_pressure = 0.0, solid_pressure = 0.0, exponent = 2.0;
  // two-stage curve (all three or none): alpha0 -> alpha_transition -> 1
  std::optional<double> transition_pressure, alpha_transition, exponent_transition;
  // the porous material's elastic wave speed c_e (0: the matrix's; Jutzi et al. 2008)
  double elastic_sound_speed = 0.0;
  SourceLocation where, soundSpeedWhere;
};

struct MaterialConfig {
  std::string name;
  double density = 0.0; // reference density rho0
  EosConfig eos;
  StrengthConfig strength;
  DamageConfig damage;
  PorosityConfig porosity;
  materials::Erosion erosion = materials::Erosion::None;
  SourceLocation where;
};

enum class ShapeType {
  Box,
  Sphere,
  Cylinder,
  Ring,
  Cone,
  Ogive,
  Polygon,
  Union,
  Difference,
  Particles
};
inline constexpr NameTable<ShapeType, 10> kShapeNames{{{{ShapeType::Box, "box"},
                                                        {ShapeType::Sphere, "sphere"},
                                                        {ShapeType::Cylinder, "cylinder"},
                                                        {ShapeType::Ring, "ring"},
                                                        {ShapeType::Cone, "cone"},
                                                        {ShapeType::Ogive, "ogive"},
                                                        {ShapeType::Polygon, "polygon"},
                                                        {ShapeType::Union, "union"},
                                                        {ShapeType::Difference, "difference"},
                                                        {ShapeType::Particles, "particles"}}}};

// Particles read from a file (a mesher's output): each one's position and the volume it stands
// for (an area in 2D and rz, the r-z half-plane's; a length in 1D). Read once by the deck reader
// (io/ParticleFile.cpp), shared by every copy of the deck.
struct ParticleCloud {
  std::string path; // absolute
  std::size_t dimension = 0;
  std::vector<double> position; // dimension values a particle, row after row
  std::vector<double> volume;
  std::size_t size() const { return volume.size(); }
  double coarsest = 0.0, finest = 0.0; // the largest and smallest volume^(1/dimension)
  std::vector<double> lo, hi;          // the positions' bounding box
};

struct ShapeConfig {
  ShapeType type = ShapeType::Box;
  std::vector<double> min, max;                  // box
  std::vector<double> center;                    // sphere, ring
  double radius = 0.0;                           // sphere, cylinder, cone and ogive (the base's)
  std::vector<double> base, axis;                // cylinder (3D); cone, ogive (2D, rz, 3D)
  double length = 0.0;                           // cylinder, cone, ogive
  double inner_radius = 0.0, outer_radius = 0.0; // ring (2D)
  double tip_radius = 0.0;                       // cone: 0 a point, else a frustum
  std::vector<std::vector<double>> points;       // polygon (2D, rz): its vertices in order
  // union: every part; difference: the part the others (parts[1...]) are cut from, parts[0].
  std::vector<ShapeConfig> parts;
  std::string file;                           // particles: the file as the deck names it
  std::shared_ptr<const ParticleCloud> cloud; // particles: the file's particles
  SourceLocation where;
};

struct LinearVelocityConfig {
  std::vector<double> center;
  std::vector<std::vector<double>> gradient; // G: v += G (x - center), dimension x dimension
};

// A standing wave's velocity: v += amplitude sin(wavevector . (x - origin)) (a bar's vibration
// mode: decks/vibrating_bar_mpm_1d.toml).
struct SineVelocityConfig {
  std::vector<double> amplitude, wavevector, origin;
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

// The lattice a body's particles are placed on (hexagonal: close-packed rows, 2D and 3D).
enum class Lattice { Cubic, Hexagonal };
inline constexpr NameTable<Lattice, 2> kLatticeNames{
    {{{Lattice::Cubic, "cubic"}, {Lattice::Hexagonal, "hexagonal"}}}};

// A body's graded spacing: `spacing` within `within` of a reference, growing by `ratio` per
// particle layer beyond it up to `max_spacing` (app/GradedSites.cpp lays the layers). The
// reference is exactly one of a point, a line {point, direction} or a plane {point, normal}.
struct GradingLine {
  std::vector<double> point, direction;
};
struct GradingPlane {
  std::vector<double> point, normal;
};
struct GradingConfig {
  double within = 0.0;
  double ratio = 1.05;
  double max_spacing = 0.0; // before run.resolution
  std::vector<double> point;
  std::optional<GradingLine> line;
  std::optional<GradingPlane> plane;
  SourceLocation where;
};

struct BodyConfig {
  std::string name;
  std::string material;    // name as in the deck
  int material_index = -1; // resolved index into Deck::materials
  ShapeConfig shape;
  double spacing = 0.0; // before run.resolution
  SourceLocation spacingWhere, velocityWhere;
  Lattice lattice = Lattice::Cubic;
  std::vector<double> velocity; // dimension entries
  std::optional<double> initial_density;
  std::optional<double> initial_specific_energy;
  std::optional<double> initial_pressure;
  double jitter = 0.0; // fraction of the spacing
  std::optional<RadialVelocityConfig> radial_velocity;
  double insert_time = 0.0;
  // Whether a body waiting for its insert_time has joined by `time` (the step before it lands on
  // insert_time, within round-off).
  bool joinedBy(double time) const { return time >= insert_time * (1.0 - 1e-12); }
  std::optional<std::vector<std::vector<double>>> lattice_transform; // dimension x dimension
  bool allow_overlap = false; // may overlap bodies listed before it
  std::optional<CantileverVelocityConfig> cantilever_velocity;
  std::optional<LinearVelocityConfig> linear_velocity;
  std::optional<SineVelocityConfig> sine_velocity;
  bool fixed = false; // held in place: v = 0, a = 0 (a clamp); still carries stress
  std::optional<GradingConfig> grading;
  SourceLocation where;
};

struct EnergySourceConfig {
  std::vector<double> center;
  double radius = 0.0;
  double energy = 0.0; // J
  SourceLocation where;
};

struct OutputConfig {
  std::string directory;
  double every = 0.0;              // s of simulated time between snapshots (0: not by time)
  std::int64_t every_steps = 0;    // steps between snapshots (0: not by steps)
  std::vector<std::string> fields; // empty: all present
  bool grid = false;               // MPM: the background grid's nodes in every snapshot (/grid)
  std::int64_t history_every_steps = 1;
  // Progress in a batch log (a file or pipe): a line every so many wall seconds and at every so
  // many percent of the end time (0: not by percent). A terminal gets a line redrawn in place.
  double progress_seconds = 30.0;
  double progress_percent = 10.0;
  // Steps of a failing particle's history: the run keeps a copy of its state at most this many
  // steps old, and on failure replays from it (0: no copy, no replay).
  std::int64_t failure_history = 20;
  // A warning when dt falls below this fraction of its median over the last 100 steps (0: off).
  double dt_warning = 0.1;
  // The run stops (exit 1, explained as a failure) when its total energy departs from the
  // initial energy plus the work of external forces by more than this fraction of the energy
  // scale, K0 + |U0| + |W| (0: never). No scheme here creates energy: a run that does is blowing
  // up, however slowly its time step falls. Not judged with a fixed body (its work is not booked).
  double max_energy_error = 1.0;
  // Particle ids whose deformation gradient and stress are written every step
  // (particles/particle_ID.ftable and .csv; `spall history`, `spall element`).
  std::vector<std::int64_t> record_particles;
  SourceLocation where, recordWhere;
};

struct CheckpointConfig {
  std::int64_t every_steps = 0;
  double every_wall_seconds = 0.0;
  int keep = 2;
  SourceLocation where;
};

// [fragments]: friends of friends at every snapshot (diagnostics/Fragments.hpp).
struct FragmentsConfig {
  double link_length = 1.5;       // in particle spacings (h / nodes_per_h)
  double damage_threshold = 0.95; // particles at or above it link to nothing
  SourceLocation where;
};

// [damping]: a = a - c v on every particle until `until` (Austin 2013, Eq. 5.1), so that a body
// brought to a confining pressure settles before the shot, in the same run.
struct DampingConfig {
  double coefficient = 0.0; // c, 1/s
  double until = 0.0;       // s
  SourceLocation where;
};

// [penetration]: penetration.csv (diagnostics/Penetration.hpp).
struct PenetrationConfig {
  std::vector<std::string> penetrator; // body names
  std::string target;                  // body name
  std::vector<double> surface;         // a point on the target's original surface
  std::vector<double> direction;       // of penetration, unit length (normalised on reading)
  SourceLocation where;
};

// A probe follows the particle nearest its position at t = 0, or stays at a point in space.
enum class ProbeTrack { Material, Space };
inline constexpr NameTable<ProbeTrack, 2> kProbeTrackNames{
    {{{ProbeTrack::Material, "material"}, {ProbeTrack::Space, "space"}}}};

struct ProbeConfig {
  std::string name;
  std::vector<double> position;
  ProbeTrack track = ProbeTrack::Material;
  std::vector<std::string> fields;
  SourceLocation where;
};

struct Deck {
  std::string path;          // the deck file as given
  std::string resolved_toml; // the deck with overrides and every applied default, as TOML text
  std::vector<DeckWarning> warnings; // plausibility: values a deck may hold but rarely means
  RunConfig run;
  SolverConfig solver;
  DecompositionConfig decomposition;
  std::vector<MaterialConfig> materials;
  std::vector<BodyConfig> bodies;
  std::vector<EnergySourceConfig> energy_sources;
  std::vector<BoundaryConfig> boundaries;
  std::optional<DampingConfig> damping;
  OutputConfig output;
  std::optional<CheckpointConfig> checkpoint;
  std::vector<ProbeConfig> probes;
  std::optional<FragmentsConfig> fragments;
  std::optional<PenetrationConfig> penetration;
};

// A shape's thinnest extent (a box's smallest side, a cylinder's smaller of diameter and length,
// a ring's wall) and the radius a penetrator of that shape presents (rz: a box on the axis is a
// cylinder of radius max r; otherwise half the thinnest extent, or the radius).
double thinnestWidth(const ShapeConfig& s);
double penetratorRadius(const ShapeConfig& s, bool rz);

// The deck as a run ran it (OUT/deck.toml): resolved_toml with output.directory set to where the
// run wrote. `spall check` passes it and `spall run` of it repeats the run bit for bit.
std::string deckAsRun(const Deck& deck, const std::string& outputDir);

// Reads, applies `--set KEY=VALUE` overrides to, and validates a deck. Throws DeckError with the
// position of the first offending value. Writes nothing.
Deck loadDeck(const std::string& path, const std::vector<std::string>& overrides = {});

// What differs between two resolved decks in the keys that shape the physics, one line per key
// ("solver.cfl: 0.3 before, 0.25 now"). A restart may change only run.end_time, run.max_steps,
// run.title, the [output], [checkpoint], [decomposition], [fragments] and [penetration] tables
// and the tables in `free` ("body.rod": restartFreeTables); everything else must be as the
// checkpoint was written. Array-of-tables entries are matched by their `name`. The differences
// in `free` go to `freeChanges`, when given (what the restart changed, for its log).
std::vector<std::string> deckPhysicsDifferences(const std::string& before, const std::string& now,
                                                const std::vector<std::string>& free = {},
                                                std::vector<std::string>* freeChanges = nullptr);

// What a restart may change besides: every key of a body that has not joined the run at the
// checkpoint's `time` (`waiting`, by body, as the checkpoint has it) and joins after it in `now`,
// and of a material no joined body uses. A settled target is shot again with another rod, speed
// or material without its pre-stress again. Throws UsageError when the bodies or materials (by
// name, in order) differ from the checkpoint's deck `before`, DeckError when a waiting body's
// insert_time is not after `time`.
std::vector<std::string> restartFreeTables(const std::string& before, const Deck& now,
                                           const std::vector<std::int64_t>& waiting, double time);

} // namespace spall
