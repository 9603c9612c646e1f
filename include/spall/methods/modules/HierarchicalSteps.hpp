#pragma once
// solver.time_bins > 1: each particle steps in its own power-of-two bin (methods/TimeBins.hpp,
// the step in methods/SphMethod.cpp). Its bin is in snapshots and checkpoints, and its
// neighbors' bins reach it with the halo (the limiter and the waking read them); where its own
// step began and ends within the run's step lives only during that step.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class HierarchicalSteps final : public Module<Dim> {
public:
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    f.timeBin = s.add<std::int32_t>("time_bin", spall::kOutput | spall::kCheckpoint | spall::kHalo);
    f.stepStart = s.add<std::int32_t>("step_start", 0);
    f.stepEnd = s.add<std::int32_t>("step_end", 0);
  }
};

} // namespace spall::methods
