#include "spall/materials/MaterialUpdate.hpp"
#include "spall/core/Threads.hpp"

#include <algorithm>
#include <numbers>
#include <type_traits>

namespace spall::materials {

namespace {

// The EOS stage of a material's particles: its EOS, or the P-alpha porous material around it,
// compacting (advance) or at the particle's distension (the pass that advances no history).
template <class E> struct EosStage {
  const E& eos;
  const std::optional<PAlpha>& porosity;
  const MaterialFields& f;
  bool advance;
  double pMin; // the material's tension limit

  EosState operator()(std::size_t i) const {
    const EosState r = state(i);
    return {std::max(r.p, pMin), r.cs};
  }

  EosState state(std::size_t i) const {
    if (!porosity) return eos.evaluate(f.rho[i], f.e[i]);
    const bool elastic = porosity->elastic();
    const PorousState s = advance ? compact(*porosity, eos, f.rho[i], f.e[i],
                                            elastic ? f.alphaPlastic[i] : f.alpha[i])
                                  : porousState(*porosity, eos, f.rho[i], f.e[i], f.alpha[i],
                                                elastic ? f.alphaPlastic[i] : f.alpha[i]);
    f.alpha[i] = s.alpha;
    if (advance && elastic) f.alphaPlastic[i] = s.alphaP;
    f.porosity[i] = 1.0 - 1.0 / s.alpha;
    if (advance && !f.returnIterations.empty()) f.returnIterations[i] = s.iterations;
    return {s.p, s.cs};
  }
};

} // namespace

bool MaterialUpdate::anyDamage() const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [](const Material& m) { return m.damage.has_value(); });
}

bool MaterialUpdate::anyFlaws() const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [](const Material& m) { return m.scalesWithDamage(); });
}

bool MaterialUpdate::anyPorosity() const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [](const Material& m) { return m.porosity.has_value(); });
}

bool MaterialUpdate::anyCap() const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [](const Material& m) { return m.cap.has_value(); });
}

bool MaterialUpdate::anyTensorDamage() const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [](const Material& m) { return m.tensorDamage(); });
}

// One visit per material, then a plain loop over its particles: no dispatch per particle. A
// damaged material's pressure is degraded as in `update` (the deviator is left as it is).
void MaterialUpdate::evaluate(const MaterialFields& f) const {
  const std::size_t n = f.rho.size();
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    const Material& mat = materials_[k];
    const double G = mat.shearModulus();
    const auto id = static_cast<std::int32_t>(k);
    if (mat.cap) {
      capPass(*mat.cap, id, f, false, 0.0);
      continue;
    }
    const bool damage = mat.damage.has_value(), scales = mat.scalesWithDamage();
    const bool tensorMode = mat.tensorDamage();
    std::visit(
        [&](const auto& eos) {
          const EosStage<std::decay_t<decltype(eos)>> stage{eos, mat.porosity, f, false, mat.pMin};
#pragma omp parallel for schedule(static) if (threaded(n))
          for (std::size_t i = 0; i < n; ++i) {
            if (f.material[i] != id) continue;
            const EosState r = stage(i);
            f.cs[i] = longitudinal(r.cs, G, f.rho[i]);
            if (tensorMode) { // which principal stresses are tensile depends on p: S follows
              const DamagedStress c = degrade(degradeTensor(r.p, f.Sintact[i], f.damageTensor[i]),
                                              f.damage[i], mat.erosion);
              f.p[i] = c.p;
              f.S[i] = c.S;
            } else {
              f.p[i] = damage ? degradedPressure(r.p, f.damage[i], scales, mat.erosion) : r.p;
            }
          }
        },
        mat.eos);
  }
}

// Per particle, the stages in order: strength (materials/Strength.hpp, the pure functions the
// single-element driver calls), then the EOS with the material's shear modulus.
void MaterialUpdate::update(const MaterialFields& f, double dt) const {
  const std::size_t n = f.rho.size();
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    const Material& mat = materials_[k];
    const auto id = static_cast<std::int32_t>(k);
    if (mat.cap) {
      capPass(*mat.cap, id, f, true, dt);
      continue;
    }
    if (!mat.strength) { // a fluid: the EOS stage alone
      std::visit(
          [&](const auto& eos) {
            const EosStage<std::decay_t<decltype(eos)>> stage{eos, mat.porosity, f, true, mat.pMin};
#pragma omp parallel for schedule(static) if (threaded(n))
            for (std::size_t i = 0; i < n; ++i) {
              if (f.material[i] != id) continue;
              const EosState r = stage(i);
              f.p[i] = r.p;
              f.cs[i] = r.cs;
            }
          },
          mat.eos);
      continue;
    }
    if (mat.damage) {
      updateDamaged(mat, id, f, dt);
      continue;
    }
    std::visit(
        [&](const auto& eos, const auto& strength) {
          const double G = strength.shearModulus();
          const EosStage<std::decay_t<decltype(eos)>> stage{eos, mat.porosity, f, true, mat.pMin};
#pragma omp parallel for schedule(static) if (threaded(n))
          for (std::size_t i = 0; i < n; ++i) {
            if (f.material[i] != id) continue;
            const StrengthState next = strength.update(
                {f.S[i], f.plasticStrain[i], f.temperature[i]}, f.L[i], dt, f.rho[i]);
            f.S[i] = next.S;
            f.plasticStrain[i] = next.plasticStrain;
            f.temperature[i] = next.temperature;
            const EosState r = stage(i);
            f.p[i] = r.p;
            f.cs[i] = longitudinal(r.cs, G, f.rho[i]);
          }
        },
        mat.eos, *mat.strength);
  }
}

// A cap material's pass: the return of materials/CapPlasticity.hpp when advancing (dt), then
// what the state means at the particle's density.
void MaterialUpdate::capPass(const CapPlasticity& cap, std::int32_t id, const MaterialFields& f,
                             bool advance, double dt) const {
#pragma omp parallel for schedule(static) if (threaded(f.rho.size()))
  for (std::size_t i = 0; i < f.rho.size(); ++i) {
    if (f.material[i] != id) continue;
    // The quasi-static state: what the particle carries less its overstress (rate dependence).
    const bool rate = cap.rateDependent();
    const CapOverstress over =
        rate ? CapOverstress{f.capOverstress[i], f.capOverstressI1[i]} : CapOverstress{};
    const CapState before{f.S[i] - over.S, f.plasticStrain[i], f.volumetricStrain[i]};
    double I1over = over.I1;
    if (advance) {
      const CapStep step = cap.update(before, f.L[i], dt, f.rho[i]);
      Mat3 S = step.state.S;
      if (rate) {
        const CapOverstress next = cap.relax(over, f.S[i], before, step.state, f.L[i], dt);
        f.capOverstress[i] = next.S, f.capOverstressI1[i] = I1over = next.I1;
        S += next.S;
      }
      f.S[i] = S;
      f.plasticStrain[i] = step.state.plasticStrain;
      f.volumetricStrain[i] = step.state.volumetricStrain;
      if (!f.returnIterations.empty()) f.returnIterations[i] = step.iterations;
    }
    const CapResponse r =
        cap.respond(f.rho[i], {f.S[i], f.plasticStrain[i], f.volumetricStrain[i]}, I1over);
    f.p[i] = r.p;
    f.cs[i] = r.cs;
    f.capPosition[i] = r.X;
    f.porosity[i] = r.phi;
    f.porePressure[i] = r.pf;
  }
}

// A material with damage: the strength model advances the intact stress (frozen once a
// zero_stress particle has failed), the EOS gives the intact pressure, the damage model advances D
// from that intact state, and the particle carries the degraded stress.
void MaterialUpdate::updateDamaged(const Material& mat, std::int32_t id, const MaterialFields& f,
                                   double dt) const {
  const std::size_t n = f.rho.size();
  const bool scales = mat.scalesWithDamage();
  const bool freezeFailed = mat.erosion == Erosion::ZeroStress;
  const bool tensorMode = mat.tensorDamage();
  std::visit(
      [&](const auto& eos, const auto& strength, const auto& damage) {
        using D = std::decay_t<decltype(damage)>;
        const double G = strength.shearModulus();
        const EosStage<std::decay_t<decltype(eos)>> stage{eos, mat.porosity, f, true, mat.pMin};
#pragma omp parallel for schedule(static) if (threaded(n))
        for (std::size_t i = 0; i < n; ++i) {
          if (f.material[i] != id) continue;
          const StrengthState before{f.Sintact[i], f.plasticStrain[i], f.temperature[i]};
          const StrengthState next = freezeFailed && f.damage[i] >= 1.0
                                         ? before
                                         : strength.update(before, f.L[i], dt, f.rho[i]);
          const EosState st = stage(i);
          const double cs = longitudinal(st.cs, G, f.rho[i]);
          if constexpr (std::is_same_v<D, GradyKipp>) {
            const double scale = f.flawScale[i];
            // R_s: the radius of the sphere of the particle's flaw volume V = scale^-m / k.
            const auto Rs = [&] {
              return std::cbrt(3.0 * (std::pow(scale, -damage.m) / damage.k) /
                               (4.0 * std::numbers::pi));
            };
            if (damage.tensor) {
              const TensorFlawState ts = advanceTensorFlaws(
                  {f.damageTensor[i], f.strainTensor[i], f.flawsActive[i], f.flawNext[i]}, f.L[i],
                  dt, damage.crackSpeed * cs, Rs(), f.flawCount[i], scale, damage.m, seed_,
                  f.id[i]);
              f.damageTensor[i] = ts.D;
              f.strainTensor[i] = ts.eps;
              f.flawsActive[i] = ts.active;
              f.flawNext[i] = ts.next;
              f.damage[i] = ts.active > 0 ? largestEigenvalue<3>(ts.D) : 0.0;
            } else {
              // Gershgorin's bound first: far from the next flaw the eigenvalue is not needed.
              const FlawState was{f.damage[i], f.flawsActive[i], f.flawNext[i]};
              const double K = f.rho[i] * st.cs * st.cs, E = 9.0 * K * G / (3.0 * K + G);
              const Tensor<3> sigma = next.S - st.p * Tensor<3>::Identity();
              if (!flawsIdle(was, E > 0.0 ? largestEigenvalueBound(sigma) / E : 0.0,
                             f.flawCount[i])) {
                const FlawState fs =
                    advanceFlaws(was, tensileStrain(st.p, next.S, K, G), dt, damage.crackSpeed * cs,
                                 Rs(), f.flawCount[i], scale, damage.m, seed_, f.id[i]);
                f.damage[i] = fs.D;
                f.flawsActive[i] = fs.active;
                f.flawNext[i] = fs.next;
              }
            }
          } else {
            f.damage[i] = damage.advance(f.damage[i], next.plasticStrain - before.plasticStrain, dt,
                                         st.p, vonMisesStress(next.S), next.temperature);
          }
          f.Sintact[i] = next.S;
          f.plasticStrain[i] = next.plasticStrain;
          f.temperature[i] = next.temperature;
          const DamagedStress carried =
              tensorMode ? degrade(degradeTensor(st.p, next.S, f.damageTensor[i]), f.damage[i],
                                   mat.erosion)
                         : degrade(st.p, next.S, f.damage[i], scales, mat.erosion);
          f.p[i] = carried.p;
          f.S[i] = carried.S;
          f.cs[i] = cs;
        }
      },
      mat.eos, *mat.strength, *mat.damage);
}

} // namespace spall::materials
