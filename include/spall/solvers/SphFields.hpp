#pragma once
// The particle fields of the SPH hydro path, registered once in the store. Snapshot names follow
// INTERFACE.md; rates and scratch sums are checkpointed (an exact restart needs the rates of the
// last step) but not written to snapshots.
#include "spall/core/ParticleStore.hpp"

namespace spall::solvers {

template <int Dim> struct SphFields {
  Field<ParticleId> id;
  Field<Vec<Dim>> x, v;
  Field<double> m, rho, e, p, cs, h;
  Field<std::int32_t> material, body;
  // Rates of the current and previous force evaluation (kick-drift-kick needs both).
  Field<Vec<Dim>> a, aOld;
  Field<double> dedt, dedtOld, drhodt, drhodtOld;
  // Per-step sums of the neighbor loop.
  Field<double> psi0;        // Owen (2010) Eq. 1, before the 1/nu root
  Field<double> muMax;       // largest viscous mu_ij, for the time step
  Field<double> divv, curlv; // Balsara switch inputs (|curl v|); registered only when used
  // Solids (registered only when a material has strength): the deviatoric stress (always 3x3:
  // the out-of-plane components of plane and uniaxial strain are real), the velocity gradient of
  // the last force evaluation (Dim x Dim, embedded in 3x3), plastic strain, temperature.
  Field<Tensor<3>> S, L;
  Field<double> plasticStrain, temperature;
  // The kernel-gradient correction B_i = M_i^-T (velocity_gradient = "corrected"), recomputed
  // by every force evaluation before the force loop, which reads it of ghosts too.
  Field<Tensor<3>> B;
  // ASPH (solver.method = "asph"): the smoothing tensor H (1/length, symmetric; eta = H x). h
  // then holds the longest axis, 1/lambda_min(H): the reach of the neighbor search and the ghosts.
  Field<Tensor<Dim>> H;

  bool anisotropic() const { return H.valid(); }

  bool hasStrength() const { return S.valid(); }

  void registerIn(ParticleStore& s, bool balsara, bool strength = false, bool corrected = false,
                  bool asph = false) {
    constexpr unsigned out = kOutput | kCheckpoint, ck = kCheckpoint, none = 0;
    id = s.add<ParticleId>("id", out);
    x = s.add<Vec<Dim>>("position", out);
    v = s.add<Vec<Dim>>("velocity", out);
    m = s.add<double>("mass", out);
    rho = s.add<double>("density", out);
    p = s.add<double>("pressure", out);
    e = s.add<double>("specific_internal_energy", out);
    cs = s.add<double>("sound_speed", out);
    material = s.add<std::int32_t>("material", out);
    body = s.add<std::int32_t>("body", out);
    h = s.add<double>("smoothing_length", ck);
    a = s.add<Vec<Dim>>("acceleration", ck);
    aOld = s.add<Vec<Dim>>("acceleration_previous", none);
    dedt = s.add<double>("specific_internal_energy_rate", ck);
    dedtOld = s.add<double>("specific_internal_energy_rate_previous", none);
    drhodt = s.add<double>("density_rate", ck);
    drhodtOld = s.add<double>("density_rate_previous", none);
    psi0 = s.add<double>("psi0", none);
    muMax = s.add<double>("mu_max", none);
    if (balsara) {
      divv = s.add<double>("velocity_divergence", ck);
      curlv = s.add<double>("velocity_curl", ck);
    }
    if (strength) {
      S = s.add<Tensor<3>>("deviatoric_stress", ck);
      L = s.add<Tensor<3>>("velocity_gradient", ck);
      plasticStrain = s.add<double>("plastic_strain", out);
      temperature = s.add<double>("temperature", out);
    }
    if (corrected) B = s.add<Tensor<3>>("kernel_correction", none);
    if (asph) {
      H = s.add<Tensor<Dim>>("smoothing_tensor", ck);
    }
  }
};

} // namespace spall::solvers
