#pragma once
// ASPH (solver.method = "asph", Owen 2010): a smoothing tensor H per particle. Round at t = 0,
// H = I/h: the ideal-H update finds the shape from the neighbors.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class SmoothingTensor final : public Module<Dim> {
public:
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f) {
    f.H = s.add<Tensor<Dim>>("smoothing_tensor",
                             spall::kCheckpoint | spall::kHalo | spall::kReflectTensor);
    f.cellMoment = s.add<Tensor<Dim>>("voronoi_second_moment", spall::kCheckpoint);
    f.cellAge = s.add<std::int32_t>("voronoi_age", spall::kCheckpoint);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override { addFields(s, f); }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      s[f.H][i] = Tensor<Dim>::Identity() / s[f.h][i];
      s[f.cellMoment][i].setZero();
      s[f.cellAge][i] = 0; // never cut: cut at the first force evaluation
    }
  }
};

} // namespace spall::methods
