#include "spall/materials/MaterialUpdate.hpp"

namespace spall::materials {

namespace {
double shearModulusOf(const Material& m) {
  return m.strength ? std::visit([](const auto& s) { return s.shearModulus(); }, *m.strength) : 0.0;
}
} // namespace

// One visit per material, then a plain loop over its particles: no dispatch per particle.
void MaterialUpdate::evaluate(const MaterialFields& f) const {
  const std::size_t n = f.rho.size();
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    const double G = shearModulusOf(materials_[k]);
    const auto id = static_cast<std::int32_t>(k);
    std::visit(
        [&](const auto& eos) {
          for (std::size_t i = 0; i < n; ++i) {
            if (f.material[i] != id) continue;
            const MaterialResponse r = evaluateEos(eos, G, f.rho[i], f.e[i]);
            f.p[i] = r.p;
            f.cs[i] = r.cs;
          }
        },
        materials_[k].eos);
  }
}

// Per particle, the stages in order: strength (materials/Strength.hpp, the pure functions the
// single-element driver calls), then the EOS with the material's shear modulus.
void MaterialUpdate::update(const MaterialFields& f, double dt) const {
  const std::size_t n = f.rho.size();
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    const Material& mat = materials_[k];
    const auto id = static_cast<std::int32_t>(k);
    if (!mat.strength) { // a fluid: the EOS stage alone
      std::visit(
          [&](const auto& eos) {
            for (std::size_t i = 0; i < n; ++i) {
              if (f.material[i] != id) continue;
              const MaterialResponse r = evaluateEos(eos, 0.0, f.rho[i], f.e[i]);
              f.p[i] = r.p;
              f.cs[i] = r.cs;
            }
          },
          mat.eos);
      continue;
    }
    std::visit(
        [&](const auto& eos, const auto& strength) {
          const double G = strength.shearModulus();
          for (std::size_t i = 0; i < n; ++i) {
            if (f.material[i] != id) continue;
            const StrengthState next = strength.update(
                {f.S[i], f.plasticStrain[i], f.temperature[i]}, f.L[i], dt, f.rho[i]);
            f.S[i] = next.S;
            f.plasticStrain[i] = next.plasticStrain;
            f.temperature[i] = next.temperature;
            const MaterialResponse r = evaluateEos(eos, G, f.rho[i], f.e[i]);
            f.p[i] = r.p;
            f.cs[i] = r.cs;
          }
        },
        mat.eos, *mat.strength);
  }
}

} // namespace spall::materials
