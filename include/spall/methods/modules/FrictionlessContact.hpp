#pragma once
// contact = "frictionless" or "auto": across a contact-group boundary SPH's force loop transmits
// each side's normal compression only (no tension, no shear) and counts the pairs' normal strain
// once the bodies touch, so it needs each neighbor's group, ghosts included;
// MPM (contact = "frictionless" only) gives each group its own velocity field on the grid.
// The groups are set where the bodies are made (app/BodyGenerator: every rank sees every body).
// SPH's pair term: Sph::RatesLoop::contactRule (src/solvers/SphRatesLoop.hpp); MPM's:
// src/solvers/MpmGridContact.hpp.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class FrictionlessContact final : public Module<Dim> {
public:
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    f.contactGroup = s.add<std::int32_t>("contact_group", kOutput | kCheckpoint | kHalo);
  }
};

} // namespace spall::methods
