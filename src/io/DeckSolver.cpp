// The [solver] table: parsed into the solvers' own configuration (solvers/Config.hpp).
#include "DeckDetail.hpp"

namespace spall::io::deck_detail {

void readSolver(const TableReader& r, SolverConfig& s) {
  r.allowOnly(*schemaKeys("solver"));
  s.where = r.where();
  s.method = r.choice("method", kSolverMethodNames, SolverMethod::Sph);
  s.mpm.where = r.where();
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
                        " configures the material point method; this deck's "
                        "method is '" +
                        std::string(kSolverMethodNames(s.method)) + "' (set method = \"mpm\")");
    const TableReader mp = TableReader(*t, r.context().child("mpm"), r.deckPath());
    mp.allowOnly(*schemaKeys("solver.mpm"));
    s.mpm.where = mp.where();
    if (const auto v = mp.number("cell_size")) {
      mp.check(*v >= 0.0, "cell_size", ">= 0 (0: twice the finest body spacing)", *v);
      s.mpm.cell_size = *v;
    }
    s.mpm.shape = mp.choice("shape", kMpmShapeNames, MpmShape::CpGimp);
    s.mpm.transfer = mp.choice("transfer", kMpmTransferNames, MpmTransfer::Flip);
    if (const auto f = mp.number("flip")) {
      mp.check(*f >= 0.0 && *f <= 1.0, "flip", "in [0, 1] (1: FLIP, 0: PIC)", *f);
      if (s.mpm.transfer == MpmTransfer::Apic && *f != 1.0)
        mp.fail("flip", mp.quoted("flip") + " blends FLIP with PIC; transfer = \"apic\" is "
                                            "neither (PIC's velocity with an affine part): "
                                            "remove flip or set it to 1");
      s.mpm.flip = *f;
    }
    if (const auto* v = mp.subtable("viscosity")) {
      const TableReader q = TableReader(*v, mp.context().child("viscosity"), mp.deckPath());
      q.allowOnly(*schemaKeys("solver.mpm.viscosity"));
      s.mpm.viscosity_linear = q.number("linear").value_or(0.0);
      s.mpm.viscosity_quadratic = q.number("quadratic").value_or(0.0);
      q.check(s.mpm.viscosity_linear >= 0.0, "linear", ">= 0", s.mpm.viscosity_linear);
      q.check(s.mpm.viscosity_quadratic >= 0.0, "quadratic", ">= 0", s.mpm.viscosity_quadratic);
    }
  }

  s.kernel = r.choice("kernel", kKernelNames, KernelType::CubicSpline);
  s.density = r.choice("density", kDensityNames, DensityMethod::Continuity);
  // The product form by default: the stability matrix (tools/stress) runs every impact of
  // unlike materials with it, and none of them with rho_squared (decks/README.md).
  s.stress_form = r.choice("stress_form", kStressFormNames, StressForm::RhoProduct);
  if (const auto v = r.number("nodes_per_h")) {
    // Owen (2010) runs 1-4; beyond 10 the neighbor lists alone outgrow any machine.
    r.check(*v >= 0.5 && *v <= 10.0, "nodes_per_h", "in [0.5, 10]", *v);
    s.nodes_per_h = *v;
  }
  // cfl above 1 is unstable by construction; a stability test may ask for it explicitly.
  const bool unstable = r.boolean("allow_unstable_cfl").value_or(false);
  if (const auto v = r.number("cfl")) {
    if (unstable)
      r.check(*v > 0.0 && *v <= 10.0, "cfl", "in (0, 10] (allow_unstable_cfl)", *v);
    else
      r.check(*v > 0.0 && *v <= 1.0, "cfl",
              "in (0, 1] (above 1 is unstable; allow_unstable_cfl = true runs it anyway)", *v);
    s.cfl = *v;
  }
  if (const auto* t = r.subtable("artificial_viscosity")) {
    const TableReader av = TableReader(*t, r.context().child("artificial_viscosity"), r.deckPath());
    av.allowOnly(*schemaKeys("solver.artificial_viscosity"));
    auto& c = s.artificial_viscosity;
    c.alpha = av.number("alpha").value_or(c.alpha);
    av.check(c.alpha >= 0.0, "alpha", ">= 0", c.alpha);
    c.beta = av.number("beta").value_or(c.beta);
    av.check(c.beta >= 0.0, "beta", ">= 0", c.beta);
    c.balsara = av.boolean("balsara").value_or(c.balsara);
    if (av.string("reconstruction")) {
      c.reconstructGiven = true;
      c.reconstruct = av.choice("reconstruction", {"linear", "none"}, "linear") == "linear";
    }
  }
  if (const auto* t = r.subtable("artificial_stress")) {
    const TableReader as = TableReader(*t, r.context().child("artificial_stress"), r.deckPath());
    as.allowOnly(*schemaKeys("solver.artificial_stress"));
    auto& c = s.artificial_stress;
    // Only epsilon turns the stress on or off: an empty table, or one with only the exponent,
    // leaves the default (on with solids, off without: io/Deck.cpp).
    c.given = as.has("epsilon");
    c.epsilon = as.number("epsilon").value_or(c.epsilon);
    as.check(c.epsilon >= 0.0 && c.epsilon <= 1.0, "epsilon", "in [0, 1] (0: off)", c.epsilon);
    c.enabled = c.epsilon > 0.0;
    if (const auto n = as.integer("exponent")) {
      as.check(*n >= 1 && *n <= 8, "exponent", "an integer in [1, 8]", static_cast<double>(*n));
      c.exponent = static_cast<int>(*n);
    }
  }
  s.velocity_gradient =
      r.choice("velocity_gradient", kVelocityGradientNames, VelocityGradient::Sph);
  // "auto" by default: bodies that collide part again (tools/stress, decks/README.md).
  s.contact = r.choice("contact", kContactNames, Contact::Auto);
  s.h_min = r.number("h_min").value_or(s.h_min);
  r.check(s.h_min >= 0.0, "h_min", ">= 0", s.h_min);
  s.h_max = r.number("h_max", true).value_or(s.h_max);
  r.check(s.h_max > s.h_min, "h_max", "> h_min (" + formatNumber(s.h_min) + ")", s.h_max);
  s.h_max_ratio = r.number("h_max_ratio").value_or(s.h_max_ratio);
  r.check(s.h_max_ratio > 0.0, "h_max_ratio", "> 0", s.h_max_ratio);
  s.h_min_ratio = r.number("h_min_ratio").value_or(s.h_min_ratio);
  r.check(s.h_min_ratio >= 0.0 && s.h_min_ratio <= s.h_max_ratio, "h_min_ratio",
          ">= 0 and <= h_max_ratio (" + formatNumber(s.h_max_ratio) + ")", s.h_min_ratio);
  s.max_aspect_ratio = r.number("max_aspect_ratio").value_or(s.max_aspect_ratio);
  r.check(s.max_aspect_ratio >= 1.0, "max_aspect_ratio", ">= 1", s.max_aspect_ratio);
  if (const auto k = r.integer("shape_interval")) {
    r.check(*k >= 1 && *k <= 64, "shape_interval", "an integer in [1, 64] (1: every step)",
            static_cast<double>(*k));
    s.shape_interval = static_cast<int>(*k);
  }
  s.neighbor_skin = r.number("neighbor_skin").value_or(s.neighbor_skin);
  r.check(s.neighbor_skin >= 0.0 && s.neighbor_skin <= 1.0, "neighbor_skin",
          "in [0, 1] (0: a search every step)", s.neighbor_skin);
}

// What the material point method does not take yet: an error where the deck asks for it (the
// method's line where the deck has no place of its own for it).
void checkMpmScope(const Deck& deck) {
  if (deck.solver.method != SolverMethod::Mpm) return;
  const auto fail = [](const SourceLocation& where, const std::string& what) {
    throw DeckError(where, what + " is not available with solver.method = \"mpm\" yet");
  };
  if (deck.decomposition.partitioner == Partitioner::Metis)
    fail(deck.solver.where, "decomposition.partitioner = \"metis\" (a graph of neighbor pairs)");
  for (const auto& b : deck.boundaries)
    if (b.type == BoundaryType::Periodic) fail(b.where, "a boundary of type 'periodic'");
}

} // namespace spall::io::deck_detail
