#pragma once
// The pair physics of the SPH force loop, one small function a term, free of loops and of how
// pairs are visited (Sph::RatesLoop in src/solvers/SphRatesLoop.hpp visits them and sums).
// Symbols as in the papers.
#include "spall/core/Types.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace spall::solvers::pair {

// Monaghan & Gingold (1983) artificial viscosity (Lam et al. 2001, Eqs. 22-24) of an approaching
// pair (v_ij . x_ij = vr < 0): mu_ij = hbar vr / (r^2 + 0.01 hbar^2),
// Pi_ij = (-alpha cbar mu_ij + beta mu_ij^2) / rhobar. Returns Pi_ij; mu_ij (for the time step)
// through `mu`.
inline double viscosity(double vr, double r2, double hbar, double cbar, double rhobar, double alpha,
                        double beta, double& mu) {
  mu = hbar * vr / (r2 + 0.01 * hbar * hbar);
  return (-alpha * cbar * mu + beta * mu * mu) / rhobar;
}

// The approach speed v_ij . x_ij of a pair from velocities reconstructed linearly to its midpoint
// (Frontiere, Raskin & Owen 2017, Sec. 2.4): v_i - L_i x_ij / 2 and v_j + L_j x_ij / 2, so
// v_ij . x_ij loses phi (a + b) / 2 with a = x_ij . L_i x_ij, b = x_ij . L_j x_ij (only the
// symmetric part of L enters). phi is van Leer's limiter of r = a / b, 4 r / (1 + r)^2 =
// 4 a b / (a + b)^2 (symmetric in i and j, so the viscosity stays antisymmetric and conserving),
// 0 where the two gradients disagree in sign: a linear field (uniform compression, shear, plastic
// flow) leaves no approach, a shock, where the gradients differ, keeps its viscosity. Never an
// approach where the pair separates. Pairs closer than the mean spacing (q = r/h below qc =
// 1/n_h) are about to interpenetrate: there phi fades as exp(-((q - qc)/0.2)^2) and the full
// viscosity returns (Rosswog 2015, Sec. 2.3: his eta_crit is this qc, his fold 0.2); without
// that, particles next to a rigid wall, reconstructed exactly from their own images, close in
// on the wall and cross it. `gate` (in [0, 1], the mean of the pair's isochoricGate) scales phi:
// the reconstruction acts where the flow changes shape, not volume.
inline double reconstructedApproach(double vr, double a, double b, double q, double qc,
                                    double gate = 1.0) {
  double phi = a * b > 0.0 ? gate * std::min(1.0, 4.0 * a * b / ((a + b) * (a + b))) : 0.0;
  if (q < qc) phi *= std::exp(-25.0 * (q - qc) * (q - qc));
  return std::min(vr - 0.5 * phi * (a + b), 0.0);
}

// How isochoric a particle's flow is: exp(-chi^2) with chi = |tr D| / |D| (Frobenius): 1 where
// the strain rate D only changes shape (plastic flow, shear), exp(-1) in uniaxial strain (a plane
// wave: chi = 1), exp(-Dim) in uniform compression. Without it the reconstruction also removes
// the viscosity inside a wave front a few particles wide, where neighbors' gradients agree: the
// front steepens and rings (an elastic pulse in a copper rod overshot its plateau by 31%; gated,
// by 0.3%). Plastic flow compresses the volume elastically only (chi of order 0.01 in a Taylor
// bar), but the SPH estimate of tr D is noisy next to free surfaces: a narrower gate (exp(-(chi /
// 0.5)^2), or the smaller of the pair's) takes the reconstruction away from the mushroom's rim
// (its face 9% narrow at the coarse resolution, against 7% with this one).
template <int Dim> double isochoricGate(const Tensor<Dim>& D) {
  const double norm2 = D.squaredNorm();
  if (norm2 == 0.0) return 1.0;
  const double tr = D.trace();
  return std::exp(-tr * tr / norm2);
}

// Balsara (1995): |div v| / (|div v| + |curl v| + 1e-4 c/h), from the previous step's sums; the
// pair's viscosity is scaled by the mean of both particles' factors.
inline double balsaraFactor(double div, double curl, double c, double h) {
  const double ad = std::abs(div);
  return ad / (ad + curl + 1.0e-4 * c / h + 1e-300);
}

// A pair's Balsara factor: the mean of its particles' f, faded back to 1 at pairs closer than
// the mean spacing (q below qc = 1/n_h) as the reconstruction fades there (reconstructedApproach:
// Rosswog 2015's guard, exp(-((q - qc)/0.2)^2)). Balsara's switch takes the viscosity out of
// shear flow, and isochoric plastic flow is such a flow (div v ~ 0: f ~ 0); but at close pairs
// the viscosity is what keeps particles from interpenetrating, whatever the flow. Without it the
// rim of a Taylor bar's mushroom spreads: 42CrMo4 at 8 particles across the radius with the
// Wendland C2 kernel, the face's 99th-percentile radius +5.7% of the finite-element face, +4.4%
// with the guard (decks/topics/taylor-bars.md).
inline double balsaraPair(double fi, double fj, double q, double qc) {
  const double f = 0.5 * (fi + fj);
  if (q >= qc) return f;
  return 1.0 - (1.0 - f) * std::exp(-25.0 * (q - qc) * (q - qc));
}

// Lam et al. (2001) Eq. 20, its isotropic part per unit m_j grad W: p_i/rho_i^2 + p_j/rho_j^2 +
// Pi_ij, or in the product form (p_i + p_j)/(rho_i rho_j) + Pi_ij (stable where heavy particles
// meet light ones under tension: copper on PMMA, density ratio 8). With the per-particle factors
// q = p/rho^2, s = 1 (rho^2 form) or q = p, s = 1/rho (product form) both are
// (q_i + q_j) s_i s_j + Pi_ij; sij = s_i s_j.
inline double pressureTerm(double qi, double qj, double sij, double Pij) {
  return (qi + qj) * sij + Pij;
}

// Gray, Monaghan & Swift (2001): in the principal frame of the Cauchy stress sigma = S - p I,
// each tensile principal stress sigma' > 0 gets R' = -epsilon sigma'/rho^2 (compressive ones
// none); R = Q R' Q^T back in the lab frame. The pair term is m_j f_ij^n (R_i + R_j) . grad W
// with f_ij = W(r_ij)/W(dp).
template <int Dim>
Tensor<Dim> artificialStress(const Tensor<3>& S, double p, double rho, double epsilon) {
  const double scale = -epsilon / (rho * rho);
  Tensor<Dim> sigma = S.template topLeftCorner<Dim, Dim>();
  sigma.diagonal().array() -= p;
  if constexpr (Dim == 1) {
    return Tensor<1>::Constant(sigma(0, 0) > 0.0 ? scale * sigma(0, 0) : 0.0);
  } else if constexpr (Dim == 2) {
    // In closed form (the eigen-solver took 8% of a 2D solid's step): the principal stresses
    // m +- r, and with one of them tensile R = scale l1 P1, P1 = (sigma - l2 I)/(l1 - l2) the
    // projector on the tensile axis. (The solver reads the lower triangle; so does this.)
    const double a = sigma(0, 0), b = sigma(1, 0), d = sigma(1, 1);
    const double m = 0.5 * (a + d), half = 0.5 * (a - d);
    const double r = std::sqrt(half * half + b * b);
    const double l1 = m + r, l2 = m - r;
    if (l1 <= 0.0) return Tensor<2>::Zero();
    Tensor<2> s;
    s << a, b, b, d;
    if (l2 > 0.0) return scale * s;
    s.diagonal().array() -= l2;
    return (scale * l1 / (2.0 * r)) * s; // l1 > 0 >= l2: 2 r = l1 - l2 >= l1 > 0
  } else {
    Eigen::SelfAdjointEigenSolver<Tensor<Dim>> eig;
    eig.computeDirect(sigma);
    Vec<Dim> rPrincipal = eig.eigenvalues();
    for (int a = 0; a < Dim; ++a) rPrincipal[a] = rPrincipal[a] > 0.0 ? scale * rPrincipal[a] : 0.0;
    const auto& Q = eig.eigenvectors();
    return Q * rPrincipal.asDiagonal() * Q.transpose();
  }
}

} // namespace spall::solvers::pair
