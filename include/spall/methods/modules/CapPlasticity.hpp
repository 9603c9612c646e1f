#pragma once
// Cap plasticity (a "cap" material, materials/CapPlasticity.hpp): the plastic volumetric strain,
// and the cap position, porosity and pore pressure it means. Uncompacted at t = 0 (the material
// pass then fills in what the start density means); MaterialUpdate advances them.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class CapPlasticity final : public Module<Dim> {
public:
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f) {
    constexpr unsigned out = spall::kOutput | spall::kCheckpoint;
    f.volumetricStrain = s.add<double>("plastic_volumetric_strain", out);
    f.capPosition = s.add<double>("cap_position", out);
    if (!f.porosity.valid()) f.porosity = s.add<double>("porosity", out);
    f.porePressure = s.add<double>("pore_pressure", out);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override { addFields(s, f); }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      s[f.volumetricStrain][i] = 0.0;
      s[f.capPosition][i] = 0.0;
      s[f.porosity][i] = 0.0;
      s[f.porePressure][i] = 0.0;
    }
  }
};

} // namespace spall::methods
