#pragma once
// A store built by hand for a unit test: the fields the modules of a configuration register, in
// the order a run registers them (app/Setup.cpp's module list).
#include "spall/core/ParticleFields.hpp"
#include "spall/methods/modules/BalsaraSwitch.hpp"
#include "spall/methods/modules/Damage.hpp"
#include "spall/methods/modules/Hydro.hpp"
#include "spall/methods/modules/KernelCorrection.hpp"
#include "spall/methods/modules/SmoothingTensor.hpp"
#include "spall/methods/modules/Strength.hpp"

namespace spall::fixtures {

struct FieldGroups {
  bool balsara = false, strength = false, corrected = false, asph = false, damage = false;
};

template <int Dim>
void registerFields(ParticleStore& s, ParticleFields<Dim>& f, FieldGroups g = {}) {
  methods::Hydro<Dim>::addFields(s, f);
  if (g.balsara) methods::BalsaraSwitch<Dim>::addFields(s, f);
  if (g.strength) methods::Strength<Dim>::addFields(s, f);
  if (g.corrected) methods::KernelCorrection<Dim>::addFields(s, f);
  if (g.asph) methods::SmoothingTensor<Dim>::addFields(s, f);
  if (g.damage) methods::Damage<Dim>::addFields(s, f, false);
}

} // namespace spall::fixtures
