#pragma once
// Damage models and erosion: pure functions of one particle's state, no particles, no MPI (the
// SPH solver and the single-element driver call the same code). A damage model advances the
// scalar damage D in [0, 1] over a step; `degrade` turns the intact material's pressure and
// deviatoric stress into what the damaged particle carries.
//
// Grady-Kipp / Benz & Asphaug (1994, 1995). Flaws follow the Weibull law n(eps) = k eps^m per unit
// volume. A flaw activates when the local tensile strain eps = sigma_1 / E (sigma_1 the largest
// principal stress of the intact material, E Young's modulus) passes its activation strain; while
// any flaw is active the crack grows at c_g, so that dD^(1/3)/dt = c_g / R_s with R_s the radius
// of the sphere of the particle's volume (the cracked fraction of that sphere, (c_g t / R_s)^3),
// and D never exceeds n_active / n_flaws: a particle is fully damaged only when all its flaws are
// active. Damaged material carries compression undiminished, (1 - D) of a tension and (1 - D) of
// the deviatoric stress. In Owen's tensor mode (2010, Sec. III) the damage is a tensor grown
// along the principal directions of a strain history (below).
//
// Johnson & Cook (1985), in the form of Austin (2013), Eq. 6.5: dD = d eps_p / eps_f, eps_f =
// [D1 + D2 exp(D3 sigma*)][1 + D4 ln rate*][1 + D5 T*], sigma* = -p / sigma_eq the stress
// triaxiality, rate* = max(eps_p rate / rate0, 1), T* the homologous temperature. The material
// keeps its full strength until D reaches 1 ("fails suddenly"); the erosion option then says what
// it carries.
//
// Erosion (Austin 2013, Sec. 6.4, Eqs. 6.11-6.14): what a fully damaged particle can carry, on
// top of its damage model's own degradation: none; no_tension (compression only, hydrostatic);
// no_shear (the hydrostatic stress, tension included); zero_stress (nothing, and its deformation
// frozen: the strength history stops advancing).
#include "spall/core/Random.hpp"
#include "spall/core/SymmetricEigen.hpp"
#include "spall/core/Types.hpp"
#include "spall/materials/Erosion.hpp"
#include "spall/materials/Strength.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <variant>

namespace spall::materials {

// damage = {type = "grady_kipp", weibull_k, weibull_m, crack_speed, mode = "scalar" | "tensor"}
struct GradyKipp {
  double k = 0.0;          // flaws per m^3 at unit strain
  double m = 0.0;          // Weibull exponent
  double crackSpeed = 0.4; // c_g over the longitudinal sound speed
  bool tensor = false;     // Owen (2010), Sec. III: damage per principal strain direction
};

// damage = {type = "johnson_cook", D1, D2, D3, D4, D5, reference_strain_rate, room_temperature,
//           melt_temperature}
struct JohnsonCookDamage {
  double D1 = 0.0, D2 = 0.0, D3 = 0.0, D4 = 0.0, D5 = 0.0;
  double rate0 = 1.0;
  double Troom = 293.0, Tmelt = 1356.0;

  // eps_f of Austin (2013), Eq. 6.5. Floored at a tiny positive strain: a parameter set whose
  // fracture strain goes negative (a large negative D3 times a high triaxiality) fails at once
  // rather than healing.
  double fractureStrain(double triaxiality, double rate, double T) const {
    const double Tstar = std::clamp((T - Troom) / (Tmelt - Troom), 0.0, 1.0);
    const double epsF = (D1 + D2 * std::exp(D3 * triaxiality)) *
                        (1.0 + D4 * std::log(std::max(rate / rate0, 1.0))) * (1.0 + D5 * Tstar);
    return std::max(epsF, 1e-12);
  }
  // D after a plastic strain increment dEps over dt; sigma* = -p / sigma_eq (0 without shear).
  double advance(double D, double dEps, double dt, double p, double sigmaEq, double T) const {
    if (dEps <= 0.0 || D >= 1.0) return D;
    const double triaxiality = sigmaEq > 0.0 ? -p / sigmaEq : 0.0;
    return std::min(1.0, D + dEps / fractureStrain(triaxiality, dEps / dt, T));
  }
};

using Damage = std::variant<GradyKipp, JohnsonCookDamage>;

// ---- Weibull flaws ---------------------------------------------------------------------------
// Benz & Asphaug (1995) scatter N ln N flaws over a body of N particles, flaw j at the strain
// where the body's expected count k V eps^m reaches j, each on a particle drawn at random, until
// every particle has one. Assigning the points of that unit-rate process in u = k V eps^m at
// random to N particles splits it into N independent unit-rate processes in u_i = k V_i eps^m
// (V_i the particle's volume), each stopped at u_i = ln N. So each particle draws its own: u_1,
// u_2, ... as sums of unit exponential deviates hashed from (seed, id, j), flaw j activating at
// eps_j = (u_j / (k V_i))^(1/m), as many as fall below ln N and at least one. The same flaws on
// any rank count and after any restart, and never stored: a particle keeps its count, how many
// are active and the next activation strain.
struct FlawSet {
  std::int32_t count = 0; // n_flaws
  double scale = 0.0;     // (k V_i)^(-1/m): eps_j = scale u_j^(1/m)
  double first = 0.0;     // eps_1, the weakest flaw's activation strain
};

// The stream of a particle's flaw deviates (distinct from jitter's).
inline constexpr std::uint64_t kFlawStream = 0x666c617773ull; // "flaws"

// The l-th unit exponential deviate of a particle's flaw process (-ln U, U in (0, 1]: 53 random
// bits, never 0).
inline double flawGap(std::uint64_t seed, std::uint64_t id, std::int32_t l) {
  const std::uint64_t bits = hashedBits(seed, id, kFlawStream + static_cast<std::uint64_t>(l));
  return -std::log(static_cast<double>((bits >> 11) + 1) * 0x1.0p-53);
}

// u_j, the j-th point (j >= 1) of the particle's unit-rate process.
inline double flawPoint(std::uint64_t seed, std::uint64_t id, std::int32_t j) {
  double u = 0.0;
  for (std::int32_t l = 1; l <= j; ++l) u += flawGap(seed, id, l);
  return u;
}

// The activation strain of flaw j (1-based) of a particle.
inline double flawStrain(std::uint64_t seed, std::uint64_t id, std::int32_t j, double scale,
                         double m) {
  return scale * std::pow(flawPoint(seed, id, j), 1.0 / m);
}

// The flaws of a particle of volume V in a body of N particles.
inline FlawSet drawFlaws(const GradyKipp& g, std::uint64_t seed, std::uint64_t id, double V,
                         std::uint64_t N) {
  const double uMax = std::log(static_cast<double>(std::max<std::uint64_t>(N, 2)));
  FlawSet f;
  f.scale = std::pow(g.k * V, -1.0 / g.m);
  double u = 0.0;
  for (std::int32_t l = 1;; ++l) {
    u += flawGap(seed, id, l);
    if (l > 1 && u > uMax) break;
    f.count = l;
    if (l == 1) f.first = f.scale * std::pow(u, 1.0 / g.m);
  }
  return f;
}

// The volume a particle's flaws live in: its own in 3D; in 1D and 2D the cube of its spacing
// (its length, or the square root of its area), i.e. the particle taken as a cell as deep as it is
// wide, so that R_s and the flaw statistics of a plane or uniaxial run are those of a 3D
// particle at the same spacing.
template <int Dim> double flawVolume(double particleMeasure) {
  const double spacing = std::pow(particleMeasure, 1.0 / Dim);
  return spacing * spacing * spacing;
}

// The Grady-Kipp state of one particle between steps.
struct FlawState {
  double D = 0.0;
  std::int32_t active = 0; // flaws activated so far (cracks do not heal)
  double next = 0.0;       // activation strain of flaw active + 1 (infinity when all are)
};

// One step of Benz & Asphaug damage: flaws whose activation strain the tensile strain eps has
// passed activate (all at once when eps jumps past several); with any active, D^(1/3) grows by
// c_g dt / R_s, D capped at active / count.
inline FlawState advanceFlaws(const FlawState& s, double eps, double dt, double cg, double Rs,
                              std::int32_t count, double scale, double m, std::uint64_t seed,
                              std::uint64_t id) {
  FlawState out = s;
  while (out.active < count && eps >= out.next) {
    ++out.active;
    out.next = out.active < count ? flawStrain(seed, id, out.active + 1, scale, m)
                                  : std::numeric_limits<double>::infinity();
  }
  if (out.active == 0 || eps <= 0.0) return out; // no growth under compression
  const double cap = static_cast<double>(out.active) / static_cast<double>(count);
  if (out.D >= cap) return out;
  const double root = std::cbrt(out.D) + cg * dt / Rs;
  out.D = std::min(cap, root * root * root);
  return out;
}

// Gershgorin's bound: no eigenvalue of M exceeds max_i (M_ii + sum_j!=i |M_ij|). The fast path of
// the damage stage: most particles, most steps, are far from their next flaw and the eigenvalues
// need not be computed.
inline double largestEigenvalueBound(const Tensor<3>& M) {
  double b = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    double r = M(i, i);
    for (int j = 0; j < 3; ++j)
      if (j != i) r += std::abs(M(i, j));
    b = std::max(b, r);
  }
  return b;
}

// Whether a step at a tensile strain of at most epsBound leaves the flaw state as it is: nothing
// to activate, and nothing to grow (no active flaw, no tension, or D at its cap).
inline bool flawsIdle(const FlawState& s, double epsBound, std::int32_t count) {
  if (epsBound >= s.next) return false;
  return s.active == 0 || epsBound <= 0.0 ||
         s.D >= static_cast<double>(s.active) / static_cast<double>(count);
}

// The local tensile strain of Benz & Asphaug: the largest principal stress of sigma = -p I + S
// over Young's modulus E = 9 K G / (3 K + G) (K = rho c_bulk^2).
inline double tensileStrain(double p, const Tensor<3>& S, double K, double G) {
  const double E = 9.0 * K * G / (3.0 * K + G);
  const Tensor<3> sigma = S - p * Tensor<3>::Identity();
  return E > 0.0 ? largestEigenvalue<3>(sigma) / E : 0.0;
}

struct DamagedStress {
  double p = 0.0;
  Tensor<3> S = Tensor<3>::Zero();
};

// ---- Tensor damage (Owen 2010, Sec. III) -------------------------------------------------------
// Damage is a symmetric tensor that grows along the principal directions of a strain tensor, a
// history variable advanced from the velocity gradient with the material's rotation (the same
// objective update as S: eps <- Q (Q eps Q^T + dt D) Q^T, the damage tensor rotated alike), so
// that cracks open across the direction the material is pulled in and turn with it. The flaws are
// the particle's Grady-Kipp flaws: the largest principal strain activates them; every direction
// whose principal strain has passed the weakest flaw's activation strain grows its damage
// d = n.D.n as the scalar model does, d^(1/3) by c_g dt / R_s, capped at n_active / n_flaws (one
// count for the particle: the flaws are not split by direction). Eigenvalues stay in [0, 1]. The
// particle's scalar `damage` is the largest: a crack through it in some direction.
struct TensorFlawState {
  Tensor<3> D = Tensor<3>::Zero(), eps = Tensor<3>::Zero();
  std::int32_t active = 0;
  double next = 0.0;
};

inline TensorFlawState advanceTensorFlaws(const TensorFlawState& s, const Tensor<3>& L, double dt,
                                          double cg, double Rs, std::int32_t count, double scale,
                                          double m, std::uint64_t seed, std::uint64_t id) {
  TensorFlawState out = s;
  const Tensor<3> Q = halfStepRotation(L, dt);
  const Tensor<3> Dsym = 0.5 * (L + L.transpose());
  out.eps = Q * (Q * s.eps * Q.transpose() + dt * Dsym) * Q.transpose();
  out.D = Q * (Q * s.D * Q.transpose()) * Q.transpose();
  if (out.active == 0 && largestEigenvalueBound(out.eps) < out.next) return out; // the fast path
  const SymmetricEigen<3> e = symmetricEigen<3>(out.eps);
  while (out.active < count && e.values[2] >= out.next) {
    ++out.active;
    out.next = out.active < count ? flawStrain(seed, id, out.active + 1, scale, m)
                                  : std::numeric_limits<double>::infinity();
  }
  if (out.active == 0) return out;
  const double cap = static_cast<double>(out.active) / static_cast<double>(count);
  const double weakest = flawStrain(seed, id, 1, scale, m);
  bool grew = false;
  for (int k = 0; k < 3; ++k) {
    if (e.values[k] < weakest) continue;
    const Vec<3> n = e.vectors.col(k);
    const double d = n.dot(out.D * n);
    if (d >= cap) continue;
    const double root = std::cbrt(std::max(d, 0.0)) + cg * dt / Rs;
    out.D += (std::min(cap, root * root * root) - d) * (n * n.transpose());
    grew = true;
  }
  if (grew) { // directions that are not exactly orthogonal to the tensor's axes: keep [0, 1]
    const SymmetricEigen<3> d = symmetricEigen<3>(0.5 * (out.D + out.D.transpose()));
    out.D = d.vectors * d.values.cwiseMax(0.0).cwiseMin(1.0).asDiagonal() * d.vectors.transpose();
  }
  return out;
}

// What a particle with the damage tensor D carries of the intact stress -p I + S: compressive
// principal stresses unchanged, the tensile part sigma+ as (I - D)^(1/2) sigma+ (I - D)^(1/2). A
// crack with normal n (D = n n^T) then transmits no tension across n and no shear along its
// plane; an isotropic D = d I gives the scalar model's (1 - d) sigma+.
inline DamagedStress degradeTensor(double p, const Tensor<3>& S, const Tensor<3>& D) {
  const Tensor<3> I = Tensor<3>::Identity();
  const Tensor<3> sigma = S - p * I;
  if (D.isZero(0.0) || largestEigenvalueBound(sigma) <= 0.0) return {p, S}; // intact, or no tension
  const SymmetricEigen<3> e = symmetricEigen<3>(sigma);
  Tensor<3> plus = Tensor<3>::Zero();
  for (int k = 0; k < 3; ++k)
    if (e.values[k] > 0.0) plus += e.values[k] * (e.vectors.col(k) * e.vectors.col(k).transpose());
  if (plus.isZero(0.0)) return {p, S};
  const SymmetricEigen<3> d = symmetricEigen<3>(D);
  const Tensor<3> R =
      d.vectors * (Vec<3>::Ones() - d.values.cwiseMax(0.0).cwiseMin(1.0)).cwiseSqrt().asDiagonal() *
      d.vectors.transpose();
  const Tensor<3> carried = sigma - plus + R * plus * R;
  const double pc = -carried.trace() / 3.0;
  return {pc, carried + pc * I};
}

// ---- What a damaged particle carries -----------------------------------------------------------

// Grady-Kipp: (1 - D) of a tension and of the deviator (Benz & Asphaug 1994); Johnson-Cook: the
// intact stress until failure. Then, for a fully damaged particle, the erosion option.
// The pressure alone (the EOS refresh, which leaves the deviator as the step left it).
inline double degradedPressure(double p, double D, bool scalesWithDamage, Erosion erosion) {
  if (scalesWithDamage && p < 0.0) p *= 1.0 - D;
  if (D < 1.0) return p;
  if (erosion == Erosion::NoTension) return std::max(p, 0.0); // Eq. 6.11
  if (erosion == Erosion::ZeroStress) return 0.0;             // Eq. 6.13
  return p;                                                   // none, no_shear (Eq. 6.12)
}

inline DamagedStress degrade(double p, const Tensor<3>& S, double D, bool scalesWithDamage,
                             Erosion erosion) {
  DamagedStress out{degradedPressure(p, D, scalesWithDamage, erosion), S};
  if (scalesWithDamage) out.S = (1.0 - D) * S;
  if (D >= 1.0 && erosion != Erosion::None) out.S.setZero(); // Eqs. 6.11-6.13: no deviator
  return out;
}

// Whether a fully damaged particle of this model and erosion carries tension: if not, the pairs
// it belongs to carry compression only (the solver's damaged-pair rule).
// Tensor damage: the erosion option on the tensor-degraded stress once a crack runs through the
// particle in some direction (its scalar damage, the largest eigenvalue, is 1).
inline DamagedStress degrade(const DamagedStress& tensorDegraded, double D, Erosion erosion) {
  return degrade(tensorDegraded.p, tensorDegraded.S, D, false, erosion);
}

inline bool failedCarriesTension(bool scalesWithDamage, Erosion erosion) {
  if (scalesWithDamage) return false;
  return erosion == Erosion::None || erosion == Erosion::NoShear;
}

} // namespace spall::materials
