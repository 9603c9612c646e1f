#pragma once
// velocity_gradient = "corrected" (Randles & Libersky 1996; Bonet & Lok 1999): the per-particle
// B = M^-T that makes the kernel gradient exact for linear fields. The solver computes it every
// evaluation; the method sends it to ghosts and wall images before the force loop, whose terms
// take B_i grad W and B_j grad W (Sph::RatesLoop, Stress::CorrectedCauchy).
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class KernelCorrection final : public Module<Dim> {
public:
  // Sent to ghosts on its own, after it is computed (not with the halo).
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f) {
    f.B = s.add<Tensor<3>>("kernel_correction", spall::kReflectTensor);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override { addFields(s, f); }
};

} // namespace spall::methods
