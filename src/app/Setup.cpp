#include "spall/app/Setup.hpp"

#include "spall/methods/modules/BalsaraSwitch.hpp"
#include "spall/methods/modules/CapPlasticity.hpp"
#include "spall/methods/modules/ConfiningPressure.hpp"
#include "spall/methods/modules/Damage.hpp"
#include "spall/methods/modules/DeformationGradient.hpp"
#include "spall/methods/modules/FixedBodies.hpp"
#include "spall/methods/modules/FrictionlessContact.hpp"
#include "spall/methods/modules/HierarchicalSteps.hpp"
#include "spall/methods/modules/Hydro.hpp"
#include "spall/methods/modules/KernelCorrection.hpp"
#include "spall/methods/modules/MaterialPoints.hpp"
#include "spall/methods/modules/PAlpha.hpp"
#include "spall/methods/modules/SmoothingTensor.hpp"
#include "spall/methods/modules/Strength.hpp"
#include "spall/methods/modules/VelocityDamping.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace spall::app {

namespace {

// The model the deck reader made (io/keys/) as an alternative of `To`, the variant the materials'
// update takes; none for a model `To` does not hold (no strength, the cap model, which is its
// own module, no damage).
template <class To, class From> std::optional<To> modelFor(const From& model) {
  return std::visit(
      [](const auto& m) -> std::optional<To> {
        if constexpr (std::is_constructible_v<To, decltype(m)>)
          return To(m);
        else
          return std::nullopt;
      },
      model);
}

std::optional<materials::Strength> buildStrength(const StrengthConfig& c) {
  return modelFor<materials::Strength>(c.model);
}

std::optional<materials::Damage> buildDamage(const DamageConfig& c) {
  return modelFor<materials::Damage>(c.model);
}

std::optional<materials::CapPlasticity> buildCap(const MaterialConfig& m) {
  if (const auto* cap = m.strength.cap()) return *cap;
  return std::nullopt;
}

std::optional<materials::PAlpha> buildPorosity(const MaterialConfig& mc,
                                               const materials::Eos& eos) {
  const PorosityConfig& c = mc.porosity;
  if (c.type != PorosityType::PAlpha) return std::nullopt;
  materials::PAlpha m;
  if (c.elastic_sound_speed > 0.0) { // Herrmann's elastic distension (materials/Porosity.hpp)
    m.cs0 = std::visit([&](const auto& e) { return e.evaluate(mc.density, 0.0).cs; }, eos);
    m.Ks = mc.density * m.cs0 * m.cs0;
    if (!(c.elastic_sound_speed < m.cs0))
      throw DeckError(c.soundSpeedWhere,
                      fmt::format("'elastic_sound_speed' must be below the sound speed of the "
                                  "matrix ({:.6g} m/s from its eos at density {:.6g} kg/m^3): "
                                  "pores make a material softer, got {:.6g}",
                                  m.cs0, mc.density, c.elastic_sound_speed));
    m.ce = c.elastic_sound_speed;
  }
  m.alpha0 = c.alpha0;
  m.Pe = c.elastic_pressure;
  m.Ps = c.solid_pressure;
  m.n = c.exponent;
  m.twoStage = c.transition_pressure.has_value();
  if (m.twoStage) {
    m.Pt = *c.transition_pressure;
    m.alphaT = *c.alpha_transition;
    m.nT = *c.exponent_transition;
  }
  // On the crush curve alpha = alpha_p + a(alpha_p) P_c(alpha_p) must stay above 1 and rise with
  // alpha_p, else the elastic part closes more pores than the plastic state leaves (alpha0 near 1
  // with a c_e far below c_s0 and a high solid_pressure).
  if (m.elastic()) {
    double before = 1.0;
    for (int k = 1; k <= 400; ++k) {
      const double x = 1.0 + (m.alpha0 - 1.0) * k / 400.0;
      const double alpha = x + m.elasticSlope(x) * m.crushPressure(x);
      if (!(alpha > before))
        throw DeckError(c.soundSpeedWhere,
                        fmt::format("'elastic_sound_speed' {:.6g} m/s is too low for this crush "
                                    "curve: at alpha_p = {:.6g} the elastic distension at the "
                                    "crush pressure ({:.6g} Pa) would close more pores than the "
                                    "plastic state leaves (alpha {:.6g}); raise it, or lower "
                                    "solid_pressure",
                                    m.ce, x, m.crushPressure(x), alpha));
      before = alpha;
    }
  }
  return m;
}

} // namespace

std::vector<materials::Material> buildMaterials(const Deck& deck) {
  std::vector<materials::Material> out;
  for (const auto& m : deck.materials) {
    // A cap material has no eos (DeckMaterial.cpp): its placeholder is never evaluated.
    const materials::Eos eos = m.strength.cap() ? materials::Eos{} : m.eos.model;
    out.push_back({eos, buildStrength(m.strength), buildDamage(m.damage), m.erosion, buildCap(m),
                   buildPorosity(m, eos), m.eos.min_pressure});
  }
  return out;
}

template <int Dim>
std::vector<std::unique_ptr<methods::Module<Dim>>> buildModules(const Deck& deck) {
  const auto& solver = deck.solver;
  const bool solids = std::any_of(deck.materials.begin(), deck.materials.end(),
                                  [](const auto& m) { return !m.strength.none(); });
  if (!solids && (solver.artificial_stress.enabled || solver.artificial_viscosity.reconstruct ||
                  solver.velocity_gradient != VelocityGradient::Sph))
    throw DeckError(solver.where,
                    "solver.artificial_stress, solver.artificial_viscosity.reconstruction and "
                    "solver.velocity_gradient act on the stress or velocity gradient of materials "
                    "with strength, and no material in this deck has one");
  std::vector<std::int32_t> fixed;
  for (std::size_t b = 0; b < deck.bodies.size(); ++b)
    if (deck.bodies[b].fixed) fixed.push_back(static_cast<std::int32_t>(b));
  std::vector<double> roomTemperature;
  for (const auto& m : deck.materials) roomTemperature.push_back(m.strength.initialTemperature());

  // The list: one line a module, in this order (the order their fields are registered in).
  std::vector<std::unique_ptr<methods::Module<Dim>>> list;
  const bool mpm =
      solver.method == SolverMethod::Mpm; // no pair loop: no viscosity, correction, contact
  list.push_back(std::make_unique<methods::Hydro<Dim>>());
  if (mpm)
    list.push_back(std::make_unique<methods::MaterialPoints<Dim>>(deck.run.geometry == Geometry::RZ,
                                                                  solver.mpm));
  if (solver.artificial_viscosity.balsara && !mpm)
    list.push_back(std::make_unique<methods::BalsaraSwitch<Dim>>());
  if (solids)
    list.push_back(std::make_unique<methods::Strength<Dim>>(
        roomTemperature, solver.artificial_viscosity.reconstruct));
  std::vector<std::optional<materials::GradyKipp>> flaws;
  bool damage = false;
  for (const auto& m : deck.materials) {
    damage = damage || !m.damage.none();
    const auto model = buildDamage(m.damage);
    const auto* g = model ? std::get_if<materials::GradyKipp>(&*model) : nullptr;
    flaws.push_back(g ? std::optional<materials::GradyKipp>(*g) : std::nullopt);
  }
  if (damage) list.push_back(std::make_unique<methods::Damage<Dim>>(flaws, deck.run.seed));
  if (std::any_of(deck.materials.begin(), deck.materials.end(),
                  [](const auto& m) { return m.strength.cap() != nullptr; }))
    list.push_back(std::make_unique<methods::CapPlasticity<Dim>>(
        std::any_of(deck.materials.begin(), deck.materials.end(), [](const auto& m) {
          return m.strength.cap() != nullptr && m.strength.cap()->rateDependent();
        })));
  if (std::any_of(deck.materials.begin(), deck.materials.end(),
                  [](const auto& m) { return m.porosity.type != PorosityType::None; })) {
    std::vector<double> alpha0;
    for (const auto& m : deck.materials)
      alpha0.push_back(m.porosity.type != PorosityType::None ? m.porosity.alpha0 : 1.0);
    const bool elastic =
        std::any_of(deck.materials.begin(), deck.materials.end(), [](const auto& m) {
          return m.porosity.type != PorosityType::None && m.porosity.elastic_sound_speed > 0.0;
        });
    list.push_back(std::make_unique<methods::PAlpha<Dim>>(alpha0, elastic));
  }
  if (solids && solver.velocity_gradient == VelocityGradient::Corrected && !mpm)
    list.push_back(std::make_unique<methods::KernelCorrection<Dim>>());
  if (solver.method == SolverMethod::Asph)
    list.push_back(std::make_unique<methods::SmoothingTensor<Dim>>());
  // MPM: "auto" is the grid's single velocity field (Uintah's default; the multi-field contact
  // is the explicit "frictionless": decks/topics/mpm.md).
  if (fieldPerBody(solver.contact) || (solver.contact == Contact::Auto && !mpm))
    list.push_back(std::make_unique<methods::FrictionlessContact<Dim>>());
  std::vector<typename methods::ConfiningPressure<Dim>::Load> loads;
  for (const auto& b : deck.boundaries)
    if (b.type == BoundaryType::Pressure) loads.push_back({b.bodyIndex, b.pressure});
  if (!loads.empty()) list.push_back(std::make_unique<methods::ConfiningPressure<Dim>>(loads));
  if (deck.damping)
    list.push_back(std::make_unique<methods::VelocityDamping<Dim>>(deck.damping->coefficient,
                                                                   deck.damping->until, fixed));
  if (!fixed.empty()) list.push_back(std::make_unique<methods::FixedBodies<Dim>>(fixed));
  if (solver.time_bins > 1) list.push_back(std::make_unique<methods::HierarchicalSteps<Dim>>());
  // The deformation gradient: for recorded particles, or when snapshots ask for it.
  const auto& out = deck.output;
  const bool recordF =
      !out.record_particles.empty() ||
      std::find(out.fields.begin(), out.fields.end(), "deformation_gradient") != out.fields.end();
  if (recordF) {
    if (!solids)
      throw DeckError(out.record_particles.empty() ? out.where : out.recordWhere,
                      "the deformation gradient integrates a solid's velocity gradient, and no "
                      "material in this deck has strength");
    list.push_back(std::make_unique<methods::DeformationGradient<Dim>>());
  }
  return list;
}

methods::MethodSetup methodSetup(const Deck& deck) {
  methods::MethodSetup s;
  s.solver = deck.solver;
  s.boundaries = deck.boundaries;
  if (deck.run.geometry == Geometry::RZ) {
    // The axis: for SPH a mirror that folds (solvers/Config.hpp), first, so that the other walls
    // image its images (the corner where a Taylor bar's axis meets its wall); for MPM a node
    // plane whose nodes keep no radial velocity.
    BoundaryConfig axis;
    axis.type = BoundaryType::RigidWall;
    axis.point = {0.0, 0.0};
    axis.normal = {1.0, 0.0};
    axis.fold = true;
    s.boundaries.insert(s.boundaries.begin(), axis);
  }
  for (std::size_t b = 0; b < deck.bodies.size(); ++b)
    if (deck.bodies[b].fixed) s.fixedBodies.push_back(static_cast<std::int32_t>(b));
  s.reproducible = deck.decomposition.reproducible;
  s.imbalanceThreshold = deck.decomposition.imbalance_threshold;
  s.timedCost = deck.decomposition.cost == BalanceCost::Timed;
  if (deck.solver.method != SolverMethod::Mpm) return s;
  double finest = std::numeric_limits<double>::infinity(), coarsest = 0.0;
  for (const auto& b : deck.bodies) {
    finest = std::min(finest, b.spacing / deck.run.resolution);
    coarsest = std::max(coarsest, b.spacing / deck.run.resolution);
  }
  auto& c = s.solver.mpm;
  c.cell_size = c.cell_size > 0.0 ? c.cell_size / deck.run.resolution : 2.0 * finest;
  // uGIMP's weights hold (partition of unity, C1) for half-widths up to half a cell; CPDI's
  // domains start as the points' boxes and are kept within a cell of half-width (methods/
  // MpmMethod): a box wider than 2 cells would be cut at once, and the domains would no longer
  // tile the body.
  const bool gimp = c.shape == MpmShape::Gimp || c.shape == MpmShape::CpGimp;
  if (c.shape != MpmShape::Linear && coarsest > (gimp ? 1.0 : 2.0) * c.cell_size * (1.0 + 1e-12))
    throw DeckError(deck.solver.mpm.where,
                    fmt::format("solver.mpm.cell_size: {:g} m (after run.resolution) is smaller "
                                "than {}the coarsest body spacing, {:g} m; {} (use a cell of at "
                                "least {}the spacing, or shape = \"linear\")",
                                c.cell_size, gimp ? "" : "half ", coarsest,
                                gimp ? "GIMP needs a point's box within half a cell"
                                     : "CPDI keeps a point's domain within a cell of half-width",
                                gimp ? "" : "half "));
  return s;
}

std::string methodSummary(const Deck& deck) {
  const auto& s = deck.solver;
  if (s.method == SolverMethod::Mpm) {
    const auto m = methodSetup(deck).solver.mpm;
    // The contact: "auto" is one field for MPM, as "welded".
    const std::string contact =
        s.contact == Contact::Friction
            ? fmt::format("friction {:g}", m.friction)
            : std::string(kContactNames(s.contact == Contact::Auto ? Contact::Welded : s.contact));
    return fmt::format("mpm {} cell {:.4g} m {} | contact {}", kMpmShapeNames(m.shape), m.cell_size,
                       m.transfer == MpmTransfer::Apic ? std::string("apic")
                                                       : fmt::format("flip {:g}", m.flip),
                       contact);
  }
  return fmt::format("{} {} n_h {:g} | density {}", kSolverMethodNames(s.method),
                     kKernelNames(s.kernel), s.nodes_per_h, kDensityNames(s.density));
}

template std::vector<std::unique_ptr<methods::Module<1>>> buildModules<1>(const Deck&);
template std::vector<std::unique_ptr<methods::Module<2>>> buildModules<2>(const Deck&);
template std::vector<std::unique_ptr<methods::Module<3>>> buildModules<3>(const Deck&);

} // namespace spall::app
