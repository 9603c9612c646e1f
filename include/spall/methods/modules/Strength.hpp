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
  // gradientInHalo: neighbors read L (the reconstructed artificial viscosity).
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f, bool gradientInHalo = false) {
    f.S = s.add<Tensor<3>>("deviatoric_stress",
                           spall::kCheckpoint | spall::kHalo | spall::kReflectTensor);
    f.L = s.add<Tensor<3>>("velocity_gradient",
                           spall::kCheckpoint |
                               (gradientInHalo ? spall::kHalo | spall::kReflectTensor : 0u));
    f.plasticStrain = s.add<double>("plastic_strain", spall::kOutput | spall::kCheckpoint);
    f.temperature = s.add<double>("temperature", spall::kOutput | spall::kCheckpoint);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    addFields(s, f, gradientInHalo_);
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
