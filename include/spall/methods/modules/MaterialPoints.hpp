#pragma once
// The material point method's particle: a box of half-width l_p = (V_0)^(1/dim) / 2 around it,
// its volume V_0 = m / rho at its start (the body's spacing on a cubic lattice), over which its
// GIMP weights average. uGIMP keeps l_p as it was made (Bardenhagen & Kober 2004, Sec. 4).
#include "spall/methods/Module.hpp"

#include <cmath>

namespace spall::methods {

template <int Dim> class MaterialPoints final : public Module<Dim> {
public:
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    f.halfWidth = s.add<double>("particle_half_width", kOutput | kCheckpoint | kHalo);
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    const auto m = s[f.m], rho = s[f.rho];
    const auto lp = s[f.halfWidth];
    for (std::size_t i = start.first; i < s.localCount(); ++i)
      lp[i] = 0.5 * std::pow(m[i] / rho[i], 1.0 / Dim);
  }
};

} // namespace spall::methods
