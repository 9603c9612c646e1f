#pragma once
// The deformation gradient of each particle (a solid's), advanced as the material sees its
// motion: with the velocity gradient L_n the material update of the step uses, held constant over
// the step, F_{n+1} = (I + dt L_n) F_n (Austin 2013, Eq. 4.9). So L_n = (F_{n+1} F_n^-1 - I)/dt
// (his Eq. 4.10), what `spall element` hands the material from a recorded F-table: the particle's
// history replays. F = I at t = 0; checkpointed, and in snapshots as `deformation_gradient`.
// It also keeps the density and energy the material update sees (the kick corrects both after
// it): a cap material's plastic return depends on that density, and a replay must use it.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class DeformationGradient final : public Module<Dim> {
public:
  // `transient`: for a failed run's replay only (its fields in no snapshot or checkpoint).
  explicit DeformationGradient(bool transient = false) : transient_(transient) {}
  // F_{n+1} = (I + dt L_n) F_n of the owned particles: snapshots ([N,3,3]) and checkpoints;
  // `transient` (a failed run's replay): neither, the fields live for the replay only.
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f, bool transient = false) {
    f.Fdef = s.add<Tensor<3>>("deformation_gradient",
                              transient ? 0u : spall::kOutput | spall::kCheckpoint);
    f.rhoUpdate = s.add<double>("update_density", transient ? 0u : unsigned{spall::kCheckpoint});
    f.eUpdate = s.add<double>("update_specific_internal_energy",
                              transient ? 0u : unsigned{spall::kCheckpoint});
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    addFields(s, f, transient_);
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      s[f.Fdef][i].setIdentity();
      s[f.rhoUpdate][i] = s[f.rho][i];
      s[f.eUpdate][i] = s[f.e][i];
    }
  }
  void beforeMaterials(ParticleStore& s, const ParticleFields<Dim>& f, double dt) const override {
    const auto F = s[f.Fdef];
    const auto L = s[f.L];
    const auto rho = s[f.rho], e = s[f.e];
    for (std::size_t i = 0; i < s.localCount(); ++i) {
      F[i] = ((Tensor<3>::Identity() + dt * L[i]) * F[i]).eval();
      s[f.rhoUpdate][i] = rho[i];
      s[f.eUpdate][i] = e[i];
    }
  }

private:
  bool transient_;
};

} // namespace spall::methods
