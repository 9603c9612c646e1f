#pragma once
// contact = "frictionless": across a body boundary the force loop transmits compression only
// (no tension, no shear), so it needs each neighbor's body, ghosts included.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class FrictionlessContact final : public Module<Dim> {
public:
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    s.addFlags(f.body.index, kHalo);
  }
};

} // namespace spall::methods
