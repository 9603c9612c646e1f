#pragma once
// Cap plasticity (a "cap" material, materials/CapPlasticity.hpp): the plastic volumetric strain,
// and the cap position, porosity and pore pressure it means. Uncompacted at t = 0 (the material
// pass then fills in what the start density means); MaterialUpdate advances them. With a
// rate-dependent cap material the overstress above the quasi-static state too (its deviator and
// I1; none at t = 0).
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class CapPlasticity final : public Module<Dim> {
public:
  explicit CapPlasticity(bool rateDependent) : rate_(rateDependent) {}

  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    constexpr unsigned out = spall::kOutput | spall::kCheckpoint;
    f.volumetricStrain = s.add<double>("plastic_volumetric_strain", out);
    f.capPosition = s.add<double>("cap_position", out);
    if (!f.porosity.valid()) f.porosity = s.add<double>("porosity", out);
    f.porePressure = s.add<double>("pore_pressure", out);
    if (rate_) {
      f.capOverstress = s.add<Tensor<3>>("cap_overstress", out);
      f.capOverstressI1 = s.add<double>("cap_overstress_i1", out);
    }
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      s[f.volumetricStrain][i] = 0.0;
      s[f.capPosition][i] = 0.0;
      s[f.porosity][i] = 0.0;
      s[f.porePressure][i] = 0.0;
      if (rate_) s[f.capOverstress][i] = Tensor<3>::Zero(), s[f.capOverstressI1][i] = 0.0;
    }
  }

private:
  bool rate_;
};

} // namespace spall::methods
