#pragma once
// Strength models: pure functions (state, L, dt) -> state for the deviatoric stress S of a
// hypoelastic-plastic solid. No particles, no MPI: the SPH solver and the single-element driver
// call the very same code. Always 3x3: in 1D (uniaxial strain) and 2D (plane strain) the
// out-of-plane deviatoric components are real and enter the yield condition.
//
// Objective rate: S is carried by the Jaumann rate, dS/dt = 2 G D' + W S - S W (Owen 2010 and
// Lam et al. 2001 name the hypoelastic form; Austin 2013, Sec. 2.3 works in the unrotated frame
// instead). Over a step the rotation is applied exactly orthogonally, in two halves around the
// strain increment: Q = (I - W dt/4)^-1 (I + W dt/4) (the Hughes & Winget 1980 rotation of half
// a step), S_new = Q (Q S Q^T + 2 G dt D') Q^T. A rigid rotation, however large, then never
// changes the invariants, and the unrotated stress of a rotating stretch is right to second
// order in dt (Austin 2013, Sec. 4.1.1.1: frame indifference).
// Plasticity: radial return to the von Mises cylinder (J2), with Johnson-Cook or Zerilli-Armstrong
// hardening, rate and thermal softening, and plastic heating dT = chi sigma_y d eps_p / (rho c_p)
// (Austin 2013, Eq. 6.7).
#include "spall/core/Types.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

namespace spall::materials {

using Mat3 = Tensor<3>;

struct StrengthState {
  Mat3 S = Mat3::Zero();      // deviatoric Cauchy stress, Pa
  double plasticStrain = 0.0; // equivalent plastic strain
  double temperature = 0.0;   // K (Johnson-Cook, Zerilli-Armstrong; others leave it alone)
};

// The rotation of half a step with the spin W of L (Hughes & Winget 1980): the objective update
// of every tensor a particle carries (S here, the damage and strain tensors of
// materials/Damage.hpp).
inline Mat3 halfStepRotation(const Mat3& L, double dt) {
  const Mat3 W = 0.5 * (L - L.transpose());
  const Mat3 I = Mat3::Identity();
  return (I - 0.25 * dt * W).inverse() * (I + 0.25 * dt * W);
}

// The elastic trial step shared by every model: rotate S with the spin, add 2 G D' dt.
inline Mat3 elasticTrial(const Mat3& S, const Mat3& L, double dt, double G) {
  const Mat3 D = 0.5 * (L + L.transpose());
  const Mat3 I = Mat3::Identity();
  const Mat3 Q = halfStepRotation(L, dt);
  const Mat3 Ddev = D - (D.trace() / 3.0) * I;
  return Q * (Q * S * Q.transpose() + (2.0 * G * dt) * Ddev) * Q.transpose();
}

// sqrt(3/2 S:S), the von Mises equivalent stress of a deviator.
inline double vonMisesStress(const Mat3& S) {
  return std::sqrt(1.5 * S.squaredNorm());
}

// sqrt(2/3 D':D'), the equivalent (total) deviatoric strain rate.
inline double equivalentStrainRate(const Mat3& L) {
  const Mat3 D = 0.5 * (L + L.transpose());
  const Mat3 Ddev = D - (D.trace() / 3.0) * Mat3::Identity();
  return std::sqrt(2.0 / 3.0 * Ddev.squaredNorm());
}

// A model's yield stress after a plastic increment d over the step, and its slope in ln d,
// d dY/dd (finite at d -> 0 for the power and log laws of the rate and hardening terms).
struct YieldPoint {
  double Y = 0.0;
  double slope = 0.0;
};

// The radial return of a model whose yield stress Y(d) grows with the plastic increment d of
// the step (through the strain and, for a rate-dependent model, the plastic rate d/dt): the d in
// (0, q/3G] with q - 3 G d = Y(d), for a trial stress q > Y(0). Newton's method in u = ln d:
// g(u) = q - 3 G e^u - Y(e^u) is decreasing and concave in u for the Johnson-Cook and
// Zerilli-Armstrong laws (e^u, the power e^(k u) of the rate and the root of the strain are
// convex in u, and so are their increasing products), so from its first step on Newton
// approaches the root from above, quadratically. In d itself the rate's power or log bends g so
// sharply near d = 0 that a secant crawls (the Illinois regula falsi this replaced took 16
// evaluations a return on the copper Taylor bar). `guess` is the step's total deviatoric
// increment, the plastic one of steady flow; the bracket [lo, hi] of the signs seen so far
// catches what no model here does (a step outside it bisects in u). Steady flow takes 3
// evaluations (test PlasticReturn.NewtonInLnDConvergesFromAnyGuess).
struct PlasticIncrement {
  double d = 0.0; // the plastic strain increment
  double Y = 0.0; // the yield stress after it
};
template <class Yield>
PlasticIncrement plasticIncrement(double q, double G, const Yield& yield, double guess) {
  const double threeG = 3.0 * G;
  double lo = 0.0, hi = q / threeG;
  double d = guess > 0.0 && guess < hi ? guess : hi;
  YieldPoint y{};
  for (int k = 0; k < 100; ++k) {
    y = yield(d);
    const double g = q - threeG * d - y.Y;
    if (std::abs(g) <= 1e-12 * q) return {d, y.Y};
    (g > 0.0 ? lo : hi) = d;
    if (hi - lo <= 1e-15 * hi) break;
    const double du = g / (threeG * d + y.slope); // u - g / g'(u)
    const double next = d * std::exp(du);
    if (!(next > lo && next < hi)) {
      d = std::sqrt(lo * hi);
      continue;
    }
    // A step below 1e-7 in u leaves an error of its square: the next iterate solves the
    // equation to 1e-14 of q, so it is the root, and its Y is q - 3 G d (no evaluation).
    if (std::abs(du) < 1e-7) return {next, q - threeG * next};
    d = next;
  }
  return {d, yield(d).Y};
}

// The return itself and its plastic heating dT = chi Y d / (rho c_p) (Austin 2013, Eq. 6.7): `out`
// holds the trial stress, of von Mises stress q > Y(0); the guess is rate dt, `rate` the step's
// equivalentStrainRate.
template <class Yield>
StrengthState plasticReturn(StrengthState out, double q, double G, const Yield& yield, double chi,
                            double rhoCp, double rate, double dt) {
  const auto [d, Y] = plasticIncrement(q, G, yield, rate * dt);
  out.S *= Y / q;
  out.plasticStrain += d;
  out.temperature += chi * Y * d / rhoCp;
  return out;
}

// strength = {type = "elastic", shear_modulus}
struct Elastic {
  double G = 0.0;
  StrengthState update(const StrengthState& s, const Mat3& L, double dt, double /*rho*/) const {
    StrengthState out = s;
    out.S = elasticTrial(s.S, L, dt, G);
    return out;
  }
  double shearModulus() const { return G; }
};

// strength = {type = "von_mises", shear_modulus, yield_stress}: perfect plasticity.
struct VonMises {
  static constexpr bool accumulatesPlasticStrain = true; // what Johnson-Cook damage reads
  double G = 0.0;
  double Y = 0.0;
  StrengthState update(const StrengthState& s, const Mat3& L, double dt, double /*rho*/) const {
    StrengthState out = s;
    out.S = elasticTrial(s.S, L, dt, G);
    const double q = vonMisesStress(out.S);
    if (q > Y) {
      // Radial return: the plastic strain increment that brings q back to Y is (q - Y) / 3G.
      out.plasticStrain += (q - Y) / (3.0 * G);
      out.S *= Y / q;
    }
    return out;
  }
  double shearModulus() const { return G; }
};

// strength = {type = "johnson_cook", shear_modulus, A, B, n, C, m, reference_strain_rate,
//             room_temperature, melt_temperature, specific_heat, taylor_quinney, strain_rate}
// sigma_y = (A + B eps_p^n)(1 + C ln max(rate/rate0, 1))(1 - T*^m), T* = (T - Troom)/(Tmelt -
// Troom) (Johnson & Cook 1983); below the reference rate the rate term is 1. The rate is, as in
// the paper, the equivalent plastic strain rate (strain_rate = "plastic", the default): the return
// finds the plastic increment d and the yield stress at the rate d/dt together, so elastic
// ringing in a particle at yield does not raise its flow stress. strain_rate = "total" takes the
// total equivalent deviatoric strain rate of the step instead (the yield scaling of codes that
// do so). At or above the melt temperature the material carries no shear (Austin 2013, Eq. 6.6).
struct JohnsonCook {
  static constexpr bool accumulatesPlasticStrain = true; // what Johnson-Cook damage reads
  double G = 0.0;
  double A = 0.0, B = 0.0, n = 1.0, C = 0.0, m = 1.0;
  double rate0 = 1.0;
  double Troom = 293.0, Tmelt = 1356.0;
  double cp = 385.0;       // specific heat, J/(kg K)
  double chi = 0.9;        // Taylor-Quinney coefficient
  bool plasticRate = true; // strain_rate = "plastic" (true) or "total"

  double thermalFactor(double T) const {
    const double Tstar = (T - Troom) / (Tmelt - Troom);
    if (Tstar <= 0.0) return 1.0;
    if (Tstar >= 1.0) return 0.0;
    return 1.0 - std::pow(Tstar, m);
  }
  double rateFactor(double rate) const { return 1.0 + C * std::log(std::max(rate / rate0, 1.0)); }
  double hardening(double eps) const { return A + B * (eps > 0.0 ? std::pow(eps, n) : 0.0); }

  // The yield stress after a plastic increment d over a step dt from plastic strain eps0, and
  // d dY/dd; `rateFactorTotal` is the rate factor of strain_rate = "total" (unused otherwise).
  YieldPoint yieldAfter(double eps0, double d, double dt, double thermal,
                        double rateFactorTotal) const {
    const double eps = eps0 + d;
    const double power = eps > 0.0 ? std::pow(eps, n) : 0.0;
    const double H = A + B * power;
    const double dH = eps > 0.0 ? B * n * power * (d / eps) : 0.0; // d dH/dd
    double R = rateFactorTotal, dR = 0.0;                          // dR: d dR/dd
    if (plasticRate) {
      const double x = d / (dt * rate0);
      R = x > 1.0 ? 1.0 + C * std::log(x) : 1.0;
      dR = x > 1.0 ? C : 0.0;
    }
    return {H * R * thermal, (dH * R + H * dR) * thermal};
  }

  StrengthState update(const StrengthState& s, const Mat3& L, double dt, double rho) const {
    StrengthState out = s;
    out.S = elasticTrial(s.S, L, dt, G);
    const double thermal = thermalFactor(s.temperature);
    if (thermal <= 0.0) { // molten
      out.S.setZero();
      return out;
    }
    // The step's equivalent strain rate: the rate factor's with strain_rate = "total", the
    // return's guess with either (computed once).
    const double rate = plasticRate ? -1.0 : equivalentStrainRate(L);
    const double rateTotal = plasticRate ? 0.0 : rateFactor(rate);
    const auto yield = [&](double d) {
      return yieldAfter(s.plasticStrain, d, dt, thermal, rateTotal);
    };
    const double q = vonMisesStress(out.S);
    if (q <= yield(0.0).Y) return out;
    return plasticReturn(out, q, G, yield, chi, rho * cp,
                         rate < 0.0 ? equivalentStrainRate(L) : rate, dt);
  }
  double shearModulus() const { return G; }
};

// strength = {type = "zerilli_armstrong", shear_modulus, C0, C1, C2, C3, C4, C5, n,
//             reference_strain_rate, room_temperature, specific_heat, taylor_quinney}
// sigma_y = C0 + (C1 + C2 eps_p^(1/2)) exp(-C3 T + C4 T ln(rate/rate0)) + C5 eps_p^n
// (Zerilli & Armstrong 1987, J. Appl. Phys. 61, 1816: Eq. 12 for fcc metals, C1 = C5 = 0, and
// Eq. 13 for bcc metals, C2 = 0; C0 = delta sigma_G + k l^(-1/2), the athermal stress and the
// grain-size term). The thermally activated part is where the temperature and the rate act: in
// an fcc metal it multiplies the strain hardening, so the rate sensitivity grows with strain
// instead of lifting the initial yield stress (Johnson-Cook's separable factor does the latter).
// T is absolute. The rate is the equivalent plastic strain rate, the rate of the thermally
// activated dislocation motion the model describes: the return finds the increment d and the
// yield stress at the rate d/dt together, as Johnson-Cook's strain_rate = "plastic". A particle
// that stops straining relaxes along the model's rate curve (stress relaxation: copper held after
// flow at 1e4/s flows at 4.7/s and 18% lower 10 us later) instead of dropping to a static curve
// at once. Plastic heating as Johnson-Cook's.
struct ZerilliArmstrong {
  static constexpr bool accumulatesPlasticStrain = true; // what Johnson-Cook damage reads
  double G = 0.0;
  double C0 = 0.0, C1 = 0.0, C2 = 0.0, C3 = 0.0, C4 = 0.0, C5 = 0.0, n = 1.0;
  double rate0 = 1.0;
  double Troom = 293.0;
  double cp = 385.0; // specific heat, J/(kg K)
  double chi = 0.9;  // Taylor-Quinney coefficient

  // exp(-C3 T + C4 T ln(rate/rate0)); 0 at rest when C4 T > 0 (the limit of rate^(C4 T)).
  double activation(double T, double rate) const {
    const double x = rate / rate0;
    if (x <= 0.0) return C4 * T > 0.0 ? 0.0 : std::exp(-C3 * T);
    return std::exp(-C3 * T + C4 * T * std::log(x));
  }
  double yieldStress(double eps, double rate, double T) const {
    const double root = eps > 0.0 ? std::sqrt(eps) : 0.0;
    const double power = eps > 0.0 && C5 != 0.0 ? C5 * std::pow(eps, n) : 0.0;
    return C0 + (C1 + C2 * root) * activation(T, rate) + power;
  }

  // The yield stress after a plastic increment d > 0 over a step dt from plastic strain eps0,
  // and d dY/dd; the activation's power of the rate, (d / (dt rate0))^(C4 T), has d dA/dd =
  // C4 T A.
  YieldPoint yieldAfter(double eps0, double d, double dt, double T) const {
    const double eps = eps0 + d;
    const double root = std::sqrt(eps);
    const double act = std::exp(-C3 * T + C4 * T * std::log(d / (dt * rate0)));
    const double power = C5 != 0.0 ? C5 * std::pow(eps, n) : 0.0;
    const double activated = (C1 + C2 * root) * act;
    return {C0 + activated + power,
            C2 * act * 0.5 * d / root + C4 * T * activated + n * power * (d / eps)};
  }

  StrengthState update(const StrengthState& s, const Mat3& L, double dt, double rho) const {
    StrengthState out = s;
    out.S = elasticTrial(s.S, L, dt, G);
    const double q = vonMisesStress(out.S);
    if (q <= yieldStress(s.plasticStrain, 0.0, s.temperature)) return out;
    const auto yield = [&](double d) { return yieldAfter(s.plasticStrain, d, dt, s.temperature); };
    return plasticReturn(out, q, G, yield, chi, rho * cp, equivalentStrainRate(L), dt);
  }
  double shearModulus() const { return G; }
};

using Strength = std::variant<Elastic, VonMises, JohnsonCook, ZerilliArmstrong>;

} // namespace spall::materials
