#pragma once
// Material strength: the deviatoric stress, the velocity gradient that advances it, plastic
// strain and temperature (materials/MaterialUpdate runs the models). Unstressed at t = 0;
// each material starts at its room temperature (0 where the model tracks none). The reconstructed
// viscosity reads the velocity gradient of neighbors: it then travels with the halo.
#include "spall/methods/Module.hpp"

#include <vector>

namespace spall::methods {

template <int Dim> class Strength final : public Module<Dim> {
public:
  Strength(std::vector<double> roomTemperature, bool gradientInHalo)
      : T0_(std::move(roomTemperature)), gradientInHalo_(gradientInHalo) {}
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    f.registerStrength(s, gradientInHalo_);
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    const auto mat = s[f.material];
    const auto T = s[f.temperature];
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      s[f.S][i].setZero();
      s[f.L][i].setZero();
      s[f.plasticStrain][i] = 0.0;
      T[i] = T0_[static_cast<std::size_t>(mat[i])];
    }
  }

private:
  std::vector<double> T0_; // by material
  bool gradientInHalo_;
};

} // namespace spall::methods
