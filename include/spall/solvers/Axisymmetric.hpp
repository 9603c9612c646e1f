#pragma once
// Axisymmetric (r-z) SPH: x = r, y = z, each particle a ring of mass m. With no dependence on
// theta the equations of motion in cylindrical coordinates are (e.g. Petschek & Libersky 1993;
// Johnson, Stryk & Beissel 1996, Sec. 3)
//   rho dv/dt = div_rz sigma + (sigma_rr, sigma_rz)/r - (sigma_tt/r) e_r
//   d rho/dt = -rho (div_rz v + v_r/r),   de/dt = sigma : D / rho,  D_tt = v_r/r.
// The planar loops sum over neighbors with each ring's area mass mu = m/(2 pi R) (its mass per
// radian per unit radius: summed, it gives the density itself), the axis being a mirror (images
// at -r keep the sums consistent up to the axis). The pair terms of the momentum and energy
// equations carry the weight Rbar_ij/R_i, Rbar = (R_i + R_j)/2, so that m_i a_i = 2 pi mu_i mu_j
// Rbar (...) is antisymmetric: momentum along z and total energy are conserved pair by pair, as
// in the planar forms (the unweighted, "area-weighted" form lost 8% of the momentum and gained
// 30% energy in a rod impact). What the weight adds, sum_j mu_j (w_ij - 1)(...) grad W, is to
// first order the (sigma_rr, sigma_rz)/(rho r) above; the hoop term -sigma_tt/(rho r) e_r is
// evaluated with the same sum, k_r = sum_j mu_j (w_ij - 1) s_j g_ij,r (~ rho/(2r), with s_j the
// stress form's factor), as -2 sigma_tt c_i k_r, so that a uniform stress is in equilibrium on
// the axis as anywhere (a local sigma_tt/(rho r) beside the summed one pushes the first rings
// outward), and e_i takes the work of that force, so that total energy stays exact.
// The kinematic rates (density, strain rate) take D_tt = v_r/r with the normalisation the planar
// sums give dv_r/dr in a uniform radial stretch (hoopRates).
#include "spall/core/Types.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace spall::solvers::rz {

// The radius of a ring as the loops see it: at least a tenth of h, so that a ring that reached
// the axis (where its image overlaps it) keeps v_r/r and m/(2 pi R) bounded. Images (x < 0)
// are rings at |x|.
inline double radius(double x, double h) {
  return std::max(std::abs(x), 0.1 * h);
}

// The ring's area mass m/(2 pi R): what the planar sums weigh a neighbor with.
inline double areaMass(double m, double R) {
  return m / (2.0 * std::numbers::pi * R);
}

// The weight of a pair's momentum and energy terms on row i: Rbar/R_i.
inline double pairWeight(double Ri, double Rj) {
  return 0.5 * (Ri + Rj) / Ri;
}

// The hoop force and its work, from k_r (above): a_r = -2 sigma_tt c k_r, de/dt = -a_r v_r, with
// sigma_tt = S_tt - p and c = 1/rho^2 (rho^2 form) or 1/rho (product form). k_r comes in two
// shares: kr from pairs that carry the full stress (sigmaTT), krAcross from pairs across a
// contact or crack, which carry -max(p, 0) I of it (sigmaAcross).
struct HoopForce {
  double ar, dedt;
};
inline HoopForce hoopForce(double kr, double sigmaTT, double sigmaAcross, double krAcross, double c,
                           double vr) {
  const double ar = -2.0 * sigmaTT * c * kr - 2.0 * sigmaAcross * c * krAcross;
  return {ar, -ar * vr};
}

// D_tt = v_r/R as the volume rate (density, div v) and as the strain rate (stress) see it: times
// -sum_j V_j x_ij,r g_ij,r with the divergence's and the velocity gradient's kernel gradients (1
// where the kernel is complete): planar rates under-read by a few percent where the particles
// are disordered or the support is cut, and an exact v_r/r beside them turns isochoric plastic
// flow into a volume change and a uniform radial stretch into S_rr != S_tt.
struct HoopRates {
  double volume, strain;
};
inline HoopRates hoopRates(double vr, double R, double mVolume, double mStrain) {
  const double Dtt = vr / R;
  return {mVolume * Dtt, mStrain * Dtt};
}

} // namespace spall::solvers::rz
