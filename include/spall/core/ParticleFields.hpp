#pragma once
// The particle record: typed handles to the fields of the store that every method, module,
// diagnostic and writer may read. The handles live here; each group's fields are registered by
// the module that owns them (methods/modules/*.hpp, addFields), with the flags that say where
// the field travels: snapshots (kOutput), checkpoints
// (kCheckpoint), remote ghosts (kHalo, kRefresh) and wall images (kReflectVector,
// kReflectTensor). Rates are
// checkpointed (an exact restart needs the rates of the last step); per-step sums and scratch
// are not. Snapshot names follow docs/reference.md; checkpointed names are part of the file format.
#include "spall/core/ParticleStore.hpp"

namespace spall {

template <int Dim> struct ParticleFields {
  Field<ParticleId> id;
  Field<Vec<Dim>> x, v;
  Field<double> m, rho, e, p, cs, h;
  Field<std::int32_t> material, body;
  // Rates of the current and previous force evaluation (kick-drift-kick needs both).
  Field<Vec<Dim>> a, aOld;
  Field<double> dedt, dedtOld, drhodt, drhodtOld;
  // Per-step sums of the neighbor loop.
  Field<double> sumWH;       // Owen (2010) Eq. 1: sum_j W^H = Psi_0^nu (the 1/nu root not taken)
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
  // The second moment of the particle's last Voronoi cell (zero where it was open) and the
  // force evaluations since it was cut, plus 1 (0: never): the shape H relaxes towards, kept
  // between cuts (solver.shape_interval).
  Field<Tensor<Dim>> cellMoment;
  Field<std::int32_t> cellAge;

  // Damage (a material with damage): D in [0, 1], read of neighbors by the damaged-pair rule; the
  // intact material's deviatoric stress (S is then what the particle carries); Grady-Kipp flaws
  // (registered only when a material has them): the count, how many are active, the scale of
  // their activation strains (eps_j = scale u_j^(1/m)) and the next one's activation strain.
  Field<double> damage;
  Field<Tensor<3>> Sintact;
  Field<Tensor<3>> Fdef; // the deformation gradient (Austin 2013, Eq. 4.9), when recorded
  // With it, the density and energy the step's material update saw (after the drift, before the
  // kick's correction): what a replay must hand the material (app/ParticleRecorder).
  Field<double> rhoUpdate, eUpdate;
  Field<std::int32_t> flawCount, flawsActive;
  Field<double> flawScale, flawNext;
  // Owen's tensor damage (mode "tensor"): the damage tensor and the strain history it grows along.
  Field<Tensor<3>> damageTensor, strainTensor;

  // Cap plasticity (a "cap" material): the plastic volumetric strain (the history), and the cap
  // position X, porosity and pore pressure it means at the particle's density.
  Field<double> volumetricStrain, capPosition, porosity, porePressure;
  Field<Tensor<3>> capOverstress; // a rate-dependent cap's overstress (deviator, I1)
  Field<double> capOverstressI1;
  // P-alpha (a material with `porosity`): the distension alpha (the history); `porosity` holds
  // 1 - 1/alpha for its particles (the cap's phi for a cap material's).
  Field<double> alpha;
  Field<double> alphaPlastic; // with elastic distension: the plastic part (the history then)

  // [fragments]: each particle's place in the fragment catalogue of the last snapshot (0: the
  // most massive fragment). Written at snapshots, not checkpointed.
  Field<std::int64_t> fragment;

  // Contact (solver.contact frictionless or auto): particles of different groups transmit only
  // compression. The group is the body, or with "auto" the bodies touching at t = 0 merged.
  Field<std::int32_t> contactGroup;

  // [[boundary]] type = "pressure" (methods/modules/ConfiningPressure.hpp): the load on each
  // owned particle's body at the force evaluation (Pa), and its share of the free surface (m^2,
  // outward) as the force loop finds it.
  Field<double> confiningPressure;
  Field<Vec<Dim>> surfaceArea;

  // solver.method = "mpm" (methods/modules/MaterialPoints.hpp): the half-width l_p of each
  // material point's box, what its GIMP weights are averaged over.
  Field<double> halfWidth;
  // shape = "cpdi": the point's domain, a parallelogram (parallelepiped) whose half-edge vectors
  // r_i = F r_i^0 are R's columns (snapshots: particle_domain[n, i, :] = r_i).
  Field<Tensor<Dim>> domain;
  // [solver.mpm] viscosity: the bulk viscosity q the point's stress carries in the next step's
  // grid force (from the last step's rate of deformation: methods/MpmMethod).
  Field<double> viscousPressure;
  // [solver.mpm] transfer = "apic": the point's velocity gradient C_p, its velocity field
  // v_p + C_p (x - x_p) about it (snapshots: affine_velocity[n, b, a] = C_ab).
  Field<Tensor<Dim>> affine;

  // solver.time_bins > 1 (methods/TimeBins.hpp): each particle's bin k (its step dt_min 2^k),
  // and the substeps of the run's step at which its own step began and ends.
  Field<std::int32_t> timeBin, stepStart, stepEnd;

  bool anisotropic() const { return H.valid(); }
  bool binned() const { return timeBin.valid(); }
  bool hasStrength() const { return S.valid(); }
  bool hasDamage() const { return damage.valid(); }
  bool hasFlaws() const { return flawCount.valid(); }
  bool hasCap() const { return volumetricStrain.valid(); }
  bool hasPAlpha() const { return alpha.valid(); }
};

} // namespace spall
