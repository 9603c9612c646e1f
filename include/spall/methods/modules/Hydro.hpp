#pragma once
// The fields every particle carries: identity, kinematics, mass, thermodynamic state, smoothing
// scale, the rates of the last two force evaluations and the per-step neighbor sums.
#include "spall/methods/Module.hpp"

namespace spall::methods {

template <int Dim> class Hydro final : public Module<Dim> {
public:
  // What every particle method carries: identity, kinematics, mass, thermodynamic state, and
  // the rates and sums of the SPH step. The neighbor search and the force loop read the first
  // group of ghosts; the density pass changes rho, p and cs after the ghosts were made.
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f) {
    constexpr unsigned out = spall::kOutput | spall::kCheckpoint, ck = spall::kCheckpoint, none = 0;
    f.id = s.add<ParticleId>("id", out | spall::kHalo);
    f.x = s.add<Vec<Dim>>("position", out | spall::kHalo);
    f.v = s.add<Vec<Dim>>("velocity", out | spall::kHalo | spall::kReflectVector);
    f.m = s.add<double>("mass", out | spall::kHalo);
    f.rho = s.add<double>("density", out | spall::kHalo | spall::kRefresh);
    f.p = s.add<double>("pressure", out | spall::kHalo | spall::kRefresh);
    f.e = s.add<double>("specific_internal_energy", out);
    f.cs = s.add<double>("sound_speed", out | spall::kHalo | spall::kRefresh);
    f.material = s.add<std::int32_t>("material", out | spall::kHalo);
    f.body = s.add<std::int32_t>("body", out);
    f.h = s.add<double>("smoothing_length", ck | spall::kHalo);
    f.a = s.add<Vec<Dim>>("acceleration", ck);
    f.aOld = s.add<Vec<Dim>>("acceleration_previous", none);
    f.dedt = s.add<double>("specific_internal_energy_rate", ck);
    f.dedtOld = s.add<double>("specific_internal_energy_rate_previous", none);
    f.drhodt = s.add<double>("density_rate", ck);
    f.drhodtOld = s.add<double>("density_rate_previous", none);
    f.sumWH = s.add<double>("sum_wh", none);
    f.muMax = s.add<double>("mu_max", none);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override { addFields(s, f); }
};

} // namespace spall::methods
