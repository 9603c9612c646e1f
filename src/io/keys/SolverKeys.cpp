// [solver] and its sub-tables: the reference's rows and the reader's reads (Keys.hpp), one
// function per table of solvers/Config.hpp, whose initializers are the defaults.
#include "Keys.hpp"

#include <fmt/format.h>

namespace spall::io::keys {

namespace {

constexpr NameTable<bool, 2> kReconstructionNames{{{{true, "linear"}, {false, "none"}}}};

template <class K> void keysOf(K& k, SolverConfig& s) {
  k.section("", "The method and its numerical options; every key has a default.");
  k.choice("method", s.method, kSolverMethodNames, keep,
           "sph: SPH; asph: ellipsoidal smoothing (Owen 2010); mpm: the material point method.");
  k.choice("kernel", s.kernel, kKernelNames, keep, "The smoothing kernel of SPH and ASPH.");
  // Owen (2010) runs 1-4; beyond 10 the neighbor lists alone outgrow any machine.
  k.number("nodes_per_h", s.nodes_per_h, keep, "", within(0.5, 10),
           "Target number of particles per smoothing scale, n_h (Owen 2010, Sec. II-A).");
  k.number("cfl", s.cfl, keep, "", above(0),
           "Courant number: the time step as a fraction of the signal's crossing time.");
  // cfl above 1 is unstable by construction; a stability test may ask for it explicitly.
  bool unstable = false;
  k.flag("allow_unstable_cfl", unstable, false,
         "Accept cfl above 1 (up to 10), which is unstable: for stability tests.");
  k.require("cfl", "<= 1, or <= 10 with allow_unstable_cfl", s.cfl <= (unstable ? 10.0 : 1.0),
            unstable ? fmt::format("must be in (0, 10] (allow_unstable_cfl), got {}",
                                   deck_detail::formatNumber(s.cfl))
                     : fmt::format("must be in (0, 1] (above 1 is unstable; allow_unstable_cfl "
                                   "= true runs it anyway), got {}",
                                   deck_detail::formatNumber(s.cfl)));
  k.choice("density", s.density, kDensityNames, keep,
           "Density by the continuity equation or by kernel sums (Lam et al. 2001, Eqs. 18, 25).");
  k.table("artificial_viscosity", "defaults", "",
          "The shock viscosity of SPH and ASPH (Monaghan & Gingold 1983).");
  k.number("h_min", s.h_min, keep, "m", atLeast(0),
           "Lower bound on the smoothing length; 0: none.");
  k.number("h_max", s.h_max, keep, "m", above("h_min", s.h_min).orInfinite(),
           "Upper bound on the smoothing length; inf: none.");
  k.number("h_max_ratio", s.h_max_ratio, keep, "", above(0),
           "h <= ratio n_h (m/rho)^(1/dim): stops h growing without end at free surfaces.");
  k.number("h_min_ratio", s.h_min_ratio, keep, "", within(0, "h_max_ratio", s.h_max_ratio),
           "h >= ratio n_h (m/rho)^(1/dim): stops h shrinking where particles pile up; 0: off.");
  k.number("max_aspect_ratio", s.max_aspect_ratio, keep, "", atLeast(1),
           "ASPH: the longest axis of the smoothing ellipsoid over its shortest, at most.");
  k.integer("shape_interval", s.shape_interval, keep, "steps", within(1, 64),
            "ASPH: steps between cuts of each Voronoi cell, the shape its ellipsoid relaxes to.");
  k.number("neighbor_skin", s.neighbor_skin, keep, "", within(0, 1),
           "Verlet lists searched this fraction wider, kept across steps; 0: search every step.");
  // 2^11 finest steps a step at most: beyond, the far field's step outlasts any signal's.
  k.integer(
      "time_bins", s.time_bins, keep, "", within(1, 12),
      "Bins of steps dt_min 2^k, k < time_bins, each particle in its own; 1: one step for all.");
  // The product form by default: the stability matrix (tools/stress) runs every impact of
  // unlike materials with it, and none of them with rho_squared (decks/README.md).
  k.choice("stress_form", s.stress_form, kStressFormNames, keep,
           "rho_squared: Lam et al. (2001), Eqs. 20-21; rho_product: for unequal densities.");
  k.table("artificial_stress", "on with a strength model, else off", "",
          "Monaghan's artificial stress against the tensile instability (Gray et al. 2001).");
  k.choice("velocity_gradient", s.velocity_gradient, kVelocityGradientNames,
           Depends{"\"corrected\" for a material with strength and grady_kipp flaws, else \"sph\""},
           "corrected: a kernel gradient exact for linear fields (Randles & Libersky 1996).");
  // "auto" by default: bodies that collide part again (tools/stress, decks/README.md).
  k.choice("contact", s.contact, kContactNames, Contact::Auto,
           "auto: welded where bodies touch at t = 0, frictionless where they meet later; "
           "friction (MPM): Coulomb's, solver.mpm.friction.");
  k.table("mpm", "defaults", "method = \"mpm\" only",
          "The material point method's grid, shape functions and transfers.");
}

template <class K> void keysOf(K& k, ArtificialViscosityConfig& c) {
  k.section("", "Monaghan & Gingold (1983) viscosity of approaching pairs (Lam et al. 2001, "
                "Eqs. 22-24).");
  k.number("alpha", c.alpha, keep, "", atLeast(0), "Linear coefficient of the viscosity.");
  k.number("beta", c.beta, keep, "", atLeast(0), "Quadratic coefficient of the viscosity.");
  k.flag("balsara", c.balsara, keep,
         "Scale the viscosity down where the flow is shear, not compression (Balsara 1995).");
  k.choice("reconstruction", c.reconstruct, kReconstructionNames,
           Depends{"\"linear\" with a strength model, else \"none\""},
           "linear: velocities reconstructed to the pair's midpoint (Frontiere et al. 2017).");
}

template <class K> void keysOf(K& k, ArtificialStressConfig& c) {
  k.section("", "Monaghan's artificial stress (Gray, Monaghan & Swift 2001); this table turns it "
                "on.");
  k.number("epsilon", c.epsilon, keep, "", within(0, 1),
           "The fraction of the tensile stress opposed, R = -epsilon sigma'/rho^2; 0: off.");
  k.integer("exponent", c.exponent, keep, "", within(1, 8),
            "The power of the pair weight f_ij = W(r_ij)/W(dp).");
}

template <class K> void keysOf(K& k, MpmConfig& c) {
  k.section("", "The material point method (method = \"mpm\"): background grid and transfers.");
  k.number("cell_size", c.cell_size, keep, "m", atLeast(0),
           "Grid cell size, divided by run.resolution; 0: twice the finest body spacing.");
  k.choice("shape", c.shape, kMpmShapeNames, keep,
           "Tent, uGIMP, GIMP following the motion (Wallstedt & Guilkey 2008), CPDI1.");
  k.choice("transfer", c.transfer, kMpmTransferNames, keep,
           "Grid to points: the FLIP/PIC blend, or APIC's affine velocity (Jiang et al. 2015).");
  k.number("flip", c.flip, keep, "", within(0, 1),
           "The blend of the flip transfer: 1 FLIP's velocity update, 0 PIC's.");
  k.require("flip", "1 with transfer = \"apic\"", c.transfer != MpmTransfer::Apic || c.flip == 1.0,
            "blends FLIP with PIC; transfer = \"apic\" is neither (PIC's velocity with an affine "
            "part): remove flip or set it to 1");
  k.table("viscosity", "none", "", "A bulk shock viscosity in compression.");
  k.number("friction", c.friction, keep, "", atLeast(0),
           "Coulomb's coefficient mu where bodies meet (contact = \"friction\"): |dv_t| <= mu "
           "dv_n.");
}

// [solver.mpm.viscosity]: two coefficients of MpmConfig.
template <class K> void viscosityKeysOf(K& k, MpmConfig& c) {
  k.section("", "q = rho (C_Q (l tr D)^2 - C_L l c tr D) in compression (von Neumann & "
                "Richtmyer 1950).");
  k.number("linear", c.viscosity_linear, keep, "", atLeast(0),
           "C_L, the linear (Landshoff) coefficient.");
  k.number("quadratic", c.viscosity_quadratic, keep, "", atLeast(0),
           "C_Q, the quadratic coefficient.");
}

const auto kKeys = [](auto& k, auto& c) -> decltype(keysOf(k, c)) { keysOf(k, c); };
const auto kViscosityKeys = [](auto& k, MpmConfig& c) { viscosityKeysOf(k, c); };

// Reads the sub-table `key` of r, if the deck has it, with `keys`; returns whether it has.
template <class T, class Keys>
bool readSubtable(const deck_detail::TableReader& r, std::string_view key, std::string_view path,
                  T& into, Keys keys) {
  const auto* t = r.subtable(key);
  if (!t) return false;
  const deck_detail::TableReader sub(*t, r.context().child(key), r.deckPath(), r.notes());
  sub.allowOnly(*deck_detail::schemaKeys(path));
  Read read(sub);
  keys(read, into);
  return true;
}

} // namespace

std::vector<KeySection> solver() {
  return {sectionOf<SolverConfig>("solver", kKeys),
          sectionOf<ArtificialViscosityConfig>("solver.artificial_viscosity", kKeys),
          sectionOf<ArtificialStressConfig>("solver.artificial_stress", kKeys),
          sectionOf<MpmConfig>("solver.mpm", kKeys),
          sectionOf<MpmConfig>("solver.mpm.viscosity", kViscosityKeys)};
}

void readSolver(const deck_detail::TableReader& r, SolverConfig& s) {
  r.allowOnly(*deck_detail::schemaKeys("solver"));
  s.where = r.where();
  s.mpm.where = r.where();
  Read read(r);
  keysOf(read, s);

  if (s.method == SolverMethod::Mpm)
    for (const char* key :
         {"kernel", "density", "stress_form", "artificial_viscosity", "artificial_stress",
          "velocity_gradient", "h_min", "h_max", "h_min_ratio", "h_max_ratio", "max_aspect_ratio",
          "shape_interval", "neighbor_skin"})
      if (r.has(key)) s.sphOnlyKeys.push_back(key);
  if (s.method == SolverMethod::Sph)
    for (const char* key : {"max_aspect_ratio", "shape_interval"})
      if (r.has(key)) s.asphOnlyKeys.push_back(key);

  if (const auto* t = r.subtable("mpm")) {
    if (s.method != SolverMethod::Mpm)
      r.fail("mpm", r.quoted("mpm") +
                        " configures the material point method; this deck's method is '" +
                        std::string(kSolverMethodNames(s.method)) + "' (set method = \"mpm\")");
    const deck_detail::TableReader mp(*t, r.context().child("mpm"), r.deckPath(), r.notes());
    s.mpm.where = mp.where();
    readSubtable(r, "mpm", "solver.mpm", s.mpm, kKeys);
    readSubtable(mp, "viscosity", "solver.mpm.viscosity", s.mpm, kViscosityKeys);
    if (s.mpm.friction > 0.0 && s.contact != Contact::Friction)
      mp.fail("friction", "acts only where bodies' velocity fields meet: set solver.contact = "
                          "\"friction\"");
  }
  if (s.contact == Contact::Friction && s.method != SolverMethod::Mpm)
    r.fail("contact", "\"friction\" (Coulomb's, between the bodies' velocity fields) is the "
                      "material point method's; SPH and ASPH have \"auto\", \"welded\" and "
                      "\"frictionless\"");
  if (s.contact == Contact::Friction && !(s.mpm.friction > 0.0))
    r.fail("contact", "\"friction\" needs Coulomb's coefficient: set [solver.mpm] friction "
                      "(> 0; without friction, contact = \"frictionless\")");
  s.velocityGradientGiven = r.has("velocity_gradient");
  auto& av = s.artificial_viscosity;
  av.balsaraWhere = s.where;
  if (readSubtable(r, "artificial_viscosity", "solver.artificial_viscosity", av, kKeys)) {
    av.reconstructGiven = r.subtable("artificial_viscosity")->contains("reconstruction");
    av.balsaraWhere =
        deck_detail::TableReader(*r.subtable("artificial_viscosity"),
                                 r.context().child("artificial_viscosity"), r.deckPath(), r.notes())
            .whereValue("balsara");
  }
  // Only epsilon turns the stress on or off: an empty table, or one with only the exponent,
  // leaves the default (on with solids, off without: io/Deck.cpp).
  auto& as = s.artificial_stress;
  if (readSubtable(r, "artificial_stress", "solver.artificial_stress", as, kKeys)) {
    as.given = r.subtable("artificial_stress")->contains("epsilon");
    as.enabled = as.epsilon > 0.0;
  }
}

} // namespace spall::io::keys
