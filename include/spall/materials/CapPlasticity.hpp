#pragma once
// strength = {type = "cap"}: two-surface plasticity for porous rock with pore fluid, after Arenisca
// (Austin 2013, ch. 4, Fig. 4.3). The model owns the whole stress: no EOS. Compression negative.
//
// Yield surface, in I1 = tr(sigma') and q = sqrt(J2) of the effective stress sigma':
//   f = q - Ff(I1) Fc(I1, X),   Ff = f_slope (peak_i1 - I1)            (linear Drucker-Prager)
//   Fc = 1 for I1 >= kappa, else sqrt(1 - ((kappa - I1)/(kappa - X))^2)  (the elliptical cap)
//   kappa - X = cap_ratio Ff(kappa)                                      (the cap's axis ratio)
// The product form makes the surface smooth at kappa (dFc/dI1 = 0 there); its corners are the
// tensile vertex (I1 = peak_i1) and the cap tip (I1 = X), both on the hydrostat.
// Crush curve (Austin Eqs. 4.5-4.6): eps_v^p = P3 (exp(P1 (X - P0)) - 1) for X < P0, continued
// by its tangent eps_v^p = P1 P3 (X - P0) for X >= P0 (Eq. 4.5's second branch written so that the
// porosity phi = 1 - exp(-(P3 + eps_v^p)) is continuous at P0); X never passes the vertex.
//
// Elasticity: I1' = 3 K (ln(rho0/rho) - eps_v^p), the volume from the density (as every EOS of
// the code; the log strain, so that 3K is the slope in any compression), and the deviator by the
// Jaumann rate with G (Strength.hpp's elasticTrial).
// Flow: deps^p = dlambda (S/(2q) - beta dF/dI1 I); beta = dilatancy where the surface dilates
// (dF/dI1 < 0, the shear side) and 1 where it compacts (the cap: hydrostatic crush must stay
// possible at any dilatancy).
// Pore fluid (our formulation): Terzaghi's effective stress, sigma = sigma' - p_f I. The fluid
// fills the pore volume phi V undrained; its volume strain is eps_f = ln(phi V / (phi0 V0)) and
// p_f = max(0, p_f0 - K_f eps_f) (it cavitates rather than carry tension). With K_f = 0 the pores
// are drained at p_f0 (a constant pore pressure).
//
// Return algorithm (ours; cf. Brannon & Leelavanichkul's vertex test, Austin Sec. 4.1.1.3): the
// deviator keeps the trial's direction, so the return is a problem in (I1, q). A point I1 of the
// surface (with X the cap the plastic volume change I1t - I1 = 3 K d eps_v^p hardens it to) is the
// answer when the trial lies on its flow direction: h(I1) = G (I1t - I1) + 9 K beta F' (qt - F) =
// 0. On the Drucker-Prager side h is linear: a closed form (no iteration). Past the vertex (h >= 0
// there) the stress is the vertex. On the cap, h > 0 at the cap tip and < 0 at the vertex: a
// bracketed root (regula falsi, Illinois variant, bisection where an end is infinite), so the
// answer is always on the surface, whatever the iteration count; the count is bounded by the
// bracket's width reaching 4 ulp (kMaxIterations).
//
// Rate dependence (Arenisca's Duvaut-Lions overstress; Brannon, "Elements of Phenomenological
// Plasticity", Eqs. 6.92-6.93): the stress relaxes toward the rate-independent (quasi-static) one
// over the time tau = T1 (1/|D|)^T2, |D| the strain rate's norm. The quasi-static state (its
// deviator, eps_v^p, the cap) follows the return above; the particle carries it plus the
// overstress, which obeys d(over)/dt = (trial rate - quasi-static rate) - over/tau, integrated
// exactly for rates constant over the step:
//   over_n+1 = over_n r + [(sigma_trial - sigma_n) - (sigma_qs,n+1 - sigma_qs,n)] (1 - r) tau/dt,
//   r = exp(-dt/tau).
// In I1 the bracket is 3K (eps_v,n+1^p - eps_v,n^p) (the trial carries no plastic volume change),
// in the deviator the elastic trial's increment of the carried deviator less the quasi-static
// deviator's. T1 = 0: rate-independent (no overstress); tau -> infinity: elastic.
#include "spall/materials/Strength.hpp"

namespace spall::materials {

struct CapState {
  Mat3 S = Mat3::Zero();         // deviatoric effective stress (the fluid carries no shear)
  double plasticStrain = 0.0;    // equivalent deviatoric plastic strain, sum of |de^p| sqrt(2/3)
  double volumetricStrain = 0.0; // plastic volumetric strain eps_v^p (compaction negative)
};

// What a state means at a density: the total pressure p = -I1'/3 + p_f, the longitudinal signal
// speed, the cap position X, the porosity and the pore pressure.
struct CapResponse {
  double p = 0.0, cs = 0.0, X = 0.0, phi = 0.0, pf = 0.0;
};

// The surface at I1 for a cap X: Ff, Fc and F' Fc (= -fs Fc^2 + Ff u / (kappa - X), u = (kappa -
// I1)/(kappa - X)): F' times Fc is finite at the cap tip, where F' is not.
struct CapShape {
  double Ff = 0.0, Fc = 1.0, FpFc = 0.0;
};

// The overstress the particle carries above the quasi-static state (rate dependence): its deviator
// and its I1.
struct CapOverstress {
  Mat3 S = Mat3::Zero();
  double I1 = 0.0;
};

struct CapStep {
  CapState state;
  int iterations = 0; // function evaluations of the return (0: elastic or closed form)
};

struct CapPlasticity {
  static constexpr int kMaxIterations = 200;

  double rho0 = 1.0;       // density at zero effective stress (the material's density)
  double K = 0.0, G = 0.0; // bulk_modulus, shear_modulus
  double peakI1 = 0.0, fSlope = 0.0, capRatio = 1.0;
  double P0 = 0.0, P1 = 0.0, P3 = 0.0; // crush curve
  bool hardening = true;
  double dilatancy = 1.0;
  double Kf = 0.0, pf0 = 0.0; // fluid_bulk_modulus, initial_pore_pressure
  double T1 = 0.0, T2 = 0.0;  // rate_t1, rate_t2: tau = T1 (1/|D|)^T2; T1 = 0 rate-independent

  double shearModulus() const { return G; }
  bool rateDependent() const { return T1 > 0.0; }
  // tau at the strain rate of L (|D| floored at 1e-15 1/s: a still particle keeps its overstress).
  double relaxationTime(const Mat3& L) const;

  // X of a plastic volumetric strain (the crush curve's inverse; P0 without hardening).
  double capPosition(double epsVp) const;
  double porosity(double epsVp) const; // Austin Eq. 4.6
  double kappa(double X) const {
    return (X + capRatio * fSlope * peakI1) / (1.0 + capRatio * fSlope);
  }
  CapShape shape(double I1, double X) const; // I1 in [X, peak_i1]
  // F(I1, X) = Ff Fc: q on the surface (0 outside [X, peak_i1]); dF/dI1 inside (X, peak_i1].
  double yieldRadius(double I1, double X) const;
  double yieldSlope(double I1, double X) const;
  // f = q - F, +infinity outside [X, peak_i1] on the hydrostat's axis.
  double yieldFunction(double I1, double q, double X) const;
  double effectiveI1(double rho, double epsVp) const;
  double porePressure(double rho, double epsVp) const;

  // I1over: the overstress's I1 (rate dependence), added to the effective stress.
  CapResponse respond(double rho, const CapState& s, double I1over = 0.0) const;
  CapStep update(const CapState& s, const Mat3& L, double dt, double rho) const;
  // The overstress after a step (rate dependence): o the one before, Sn the deviator the particle
  // carried, qs0 and qs1 the quasi-static states before and after the step's return.
  CapOverstress relax(const CapOverstress& o, const Mat3& Sn, const CapState& qs0,
                      const CapState& qs1, const Mat3& L, double dt) const;
  // The density at which an unyielded element (eps_v^p = 0) carries the total pressure p: a
  // body's initial_pressure. nullopt when that effective stress is outside the yield surface.
  std::optional<double> densityForPressure(double p) const;
};

} // namespace spall::materials
