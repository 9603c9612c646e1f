#pragma once
// The fields every particle carries: identity, kinematics, mass, thermodynamic state, smoothing
// scale, the rates of the last two force evaluations and the per-step neighbor sums.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class Hydro final : public Module<Dim> {
public:
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override { f.registerCommon(s); }
};

} // namespace spall::methods
