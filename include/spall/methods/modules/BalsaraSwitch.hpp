#pragma once
// Balsara (1995): the artificial viscosity of a pair scaled by |div v| / (|div v| + |curl v|),
// which damps it in shear. The force loop measures div v and curl v; the next loop reads them of
// both particles (neighbors too: they travel with the halo). The pair terms: Sph::RatesLoop's
// viscosity and balsaraSums (src/solvers/SphRatesLoop.hpp).
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class BalsaraSwitch final : public Module<Dim> {
public:
  // Balsara (1995): div v and |curl v| of the last force loop, read of neighbors.
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f) {
    f.divv = s.add<double>("velocity_divergence", spall::kCheckpoint | spall::kHalo);
    f.curlv = s.add<double>("velocity_curl", spall::kCheckpoint | spall::kHalo);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override { addFields(s, f); }
};

} // namespace spall::methods
