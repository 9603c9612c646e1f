#pragma once
// One per-particle material update, shared by SPH, ASPH, MPM and the single-element driver: (rho,
// e, L, dt, history) -> (p, S, cs, history). It runs the stages of a material in order, in one
// pass: strength (the deviatoric stress over dt, from the velocity gradient), the equation of
// state, then damage (which degrades what the intact material would carry: materials/Damage.hpp);
// porosity slots in as a further stage. A cap material (materials/CapPlasticity.hpp) is one stage
// that owns the whole stress: no EOS. The evaluation without dt advances no history: the EOS-only
// refresh after a density sum or a correction. A solid carries shear waves too: its signal speed
// (time step, viscosity) is the longitudinal one, sqrt(cs^2 + 4G/(3 rho)).
#include "spall/materials/CapPlasticity.hpp"
#include "spall/materials/Damage.hpp"
#include "spall/materials/Eos.hpp"
#include "spall/materials/Porosity.hpp"
#include "spall/materials/Strength.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace spall::materials {

struct Material {
  Eos eos;
  std::optional<Strength> strength;            // none: a fluid
  std::optional<Damage> damage = std::nullopt; // needs strength
  Erosion erosion = Erosion::None;
  std::optional<CapPlasticity> cap = std::nullopt; // the whole stress: eos and strength unused
  std::optional<PAlpha> porosity = std::nullopt;   // P-alpha around the eos
  // The EOS's tension limit: p = max(p_eos, pMin) (a hydrodynamic spall cutoff, as hydrocodes'
  // minimum pressure). Without damage the Mie-Gruneisen form carries any tension a stretched
  // particle asks of it (-40 GPa at 0.7 rho0 in copper); e falls under compression in tension,
  // which deepens the tension, and a hot jet tip ran away so (decks/topics/penetration.md).
  double pMin = -std::numeric_limits<double>::infinity();

  bool solid() const { return strength.has_value() || cap.has_value(); }
  double shearModulus() const {
    if (cap) return cap->G;
    return strength ? std::visit([](const auto& s) { return s.shearModulus(); }, *strength) : 0.0;
  }
  bool scalesWithDamage() const { return damage && std::holds_alternative<GradyKipp>(*damage); }
  bool tensorDamage() const { return scalesWithDamage() && std::get<GradyKipp>(*damage).tensor; }
  // A fully damaged particle of this material carries no tension (the damaged-pair rule).
  bool failedCarriesNoTension() const {
    return damage && !failedCarriesTension(scalesWithDamage(), erosion);
  }
};

// The signal speed of a solid of shear modulus G (0: a fluid) from its bulk one.
inline double longitudinal(double cs, double G, double rho) {
  return G > 0.0 ? std::sqrt(cs * cs + 4.0 * G / (3.0 * rho)) : cs;
}

// The per-particle fields of the owned particles a material pass reads and writes. The strength
// fields are empty when no material has strength, the damage fields when none has damage, the
// flaw fields when none has Grady-Kipp flaws. With damage, S is what the particle carries and
// Sintact the intact material's stress (the strength model's history).
struct MaterialFields {
  std::span<const double> rho, e;
  std::span<const std::int32_t> material;
  std::span<double> p, cs;
  std::span<const Tensor<3>> L;
  std::span<Tensor<3>> S;
  std::span<double> plasticStrain, temperature;
  std::span<const ParticleId> id = {};
  std::span<double> damage = {};
  std::span<Tensor<3>> Sintact = {};
  std::span<const std::int32_t> flawCount = {};
  std::span<std::int32_t> flawsActive = {};
  std::span<const double> flawScale = {};
  std::span<double> flawNext = {};
  std::span<Tensor<3>> damageTensor = {}, strainTensor = {}; // tensor damage
  // Cap materials: the plastic volumetric strain (their history), and what it means at the
  // particle's density: cap position X, porosity, pore pressure. returnIterations (optional: the
  // single-element driver) receives each update's iteration count.
  std::span<double> volumetricStrain = {}, capPosition = {}, porosity = {}, porePressure = {};
  std::span<std::int32_t> returnIterations = {};
  // Rate-dependent cap materials: the overstress above the quasi-static state (S carries both).
  std::span<Tensor<3>> capOverstress = {};
  std::span<double> capOverstressI1 = {};
  // P-alpha materials: the distension alpha (the history; `porosity` is 1 - 1/alpha there).
  // returnIterations then receives the EOS evaluations of the compaction solve.
  std::span<double> alpha = {};
  // With elastic distension (elastic_sound_speed): the plastic distension alpha_p, the history
  // then (alpha = alpha_p + the elastic part; materials/Porosity.hpp).
  std::span<double> alphaPlastic = {};
};

class MaterialUpdate {
public:
  // seed: run.seed, from which (with the particle id) Grady-Kipp flaws are drawn.
  explicit MaterialUpdate(std::vector<Material> materials, std::uint64_t seed = 1)
      : materials_(std::move(materials)), seed_(seed) {}

  const std::vector<Material>& materials() const { return materials_; }
  // p and cs from (rho, e): no history advances.
  void evaluate(const MaterialFields& f) const;
  // S, plastic strain and temperature over dt from L (materials with strength), then p and cs,
  // then the damage of materials that have it.
  void update(const MaterialFields& f, double dt) const;
  bool anyDamage() const;
  bool anyFlaws() const;
  bool anyTensorDamage() const;
  bool anyCap() const;
  bool anyPorosity() const;

private:
  void capPass(const CapPlasticity& cap, std::int32_t id, const MaterialFields& f, bool advance,
               double dt) const;
  void updateDamaged(const Material& mat, std::int32_t id, const MaterialFields& f,
                     double dt) const;

  std::vector<Material> materials_;
  std::uint64_t seed_;
};

} // namespace spall::materials
