#pragma once
// porosity = {type = "p_alpha"}: sub-resolution porosity around any EOS (Herrmann 1969; Jutzi,
// Benz & Michel 2008). The distension alpha = rho_s / rho >= 1 relates the bulk density rho to the
// matrix density rho_s; the bulk pressure is P = P_eos(alpha rho, e) / alpha. Compaction follows a
// crush curve alpha_c(P) and is irreversible:
//   alpha = min(alpha_c(P(alpha)), alpha_old)                                         (1)
// One stage: alpha_c = alpha0 for P <= Pe, 1 + (alpha0 - 1) ((Ps - P)/(Ps - Pe))^n between, 1 from
// Ps (the GASPHiA note's form with the exponent n). Two stages (after Jutzi et al.; our joining):
// alpha0 -> alpha_t over (Pe, Pt] with the exponent n_t, alpha_t -> 1 over (Pt, Ps] with n:
//   alpha_c = alpha_t + (alpha0 - alpha_t) ((Pt - P)/(Pt - Pe))^n_t,  Pe < P <= Pt
//   alpha_c = 1 + (alpha_t - 1) ((Ps - P)/(Ps - Pt))^n,              Pt < P < Ps
// continuous at Pe, Pt and Ps.
// Eq. (1) is the GASPHiA note's F(alpha) = alpha - min(alpha_c(P(alpha)), alpha_old) = 0. We solve
// the same root as G(alpha) = P(alpha) - P_c(alpha) = 0 with P_c the inverse curve: alpha_c(P) <
// alpha_old exactly when P > P_c(alpha_old), so G(alpha_old) <= 0 means no compaction (one EOS
// evaluation), and G(1) >= 0 full compaction. G is smooth and monotonic across the crush range,
// where F is flat (slope 1) outside a window ~(Ps - Pe)/K wide in which its slope is hundreds:
// Newton on F bisects ~10 times before it finds the window (17 evaluations for a stiff matrix,
// 42 for a full crush; measured), on G it converges in a few. The note's safe Newton: the bracket
// [1, alpha_old] shrinks with every evaluation, and a Newton step that leaves it, or follows a
// step that did not halve |G|, is replaced by bisection; stops when the step is below 1e-12 in
// alpha (the note: below 1e-7 keeps the damage field free of oscillations; 1e-12 costs one
// Newton step more). In double.
// Sound speed: at fixed alpha dP/drho = dP_eos/drho_s, the matrix's c_s.
// Elastic distension (elastic_sound_speed c_e, optional): the porous material's elastic waves run
// at c(alpha) = h(alpha) c_s, h = 1 + (alpha - 1)(c_e/c_s0 - 1)/(alpha0 - 1), linear from the
// matrix's c_s at alpha = 1 to c_e at alpha0 (Jutzi et al. 2008). That speed needs a reversible
// distension: c^2 = dP/drho with P = P_eos(alpha rho)/alpha gives dalpha/dP = alpha^2/K_s (1 -
// 1/h^2), K_s = rho_s0 c_s0^2 (Herrmann 1969; the P dalpha term neglected, P << K_s). We write
// the distension as a plastic part alpha_p, which follows Eq. (1) in place of alpha, and an
// elastic part linear in P over the elastic range (strains ~P/K_s):
//   alpha = alpha_p + a(alpha_p) P,  a = alpha_p^2/K_s (1 - 1/h(alpha_p)^2) <= 0          (2)
// so that unloading and reloading at a fixed alpha_p are reversible, and a = 0 at alpha_p = 1.
// The update first solves Eq. (2) at alpha_p_old for alpha (elastic trial: alpha - alpha_p - a
// P(alpha) = 0, monotonic, Newton), and if P(alpha) > P_c(alpha_p_old) solves G(alpha_p) =
// P(alpha(alpha_p)) - P_c(alpha_p) = 0 as above with alpha(alpha_p) from Eq. (2) at P_c(alpha_p)
// (the plastic state lies on the crush curve). Without c_e, a = 0: alpha = alpha_p.
#include "spall/materials/Eos.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall::materials {

struct PAlpha {
  static constexpr int kMaxIterations = 100;
  static constexpr double kTolerance = 1e-12; // in alpha

  double alpha0 = 1.0;       // initial distension (at and below the elastic pressure)
  double Pe = 0.0, Ps = 0.0; // elastic_pressure, solid_pressure
  double n = 2.0;            // exponent (of the last stage)
  bool twoStage = false;
  double Pt = 0.0, alphaT = 1.0,
         nT = 1.0; // transition_pressure, alpha_transition, exponent_transition

  // Elastic distension: c_e (0: none), the matrix's reference sound speed c_s0 and bulk modulus
  // K_s = rho_s0 c_s0^2.
  double ce = 0.0, cs0 = 0.0, Ks = 0.0;
  bool elastic() const { return ce > 0.0; }
  // c(alpha)/c_s (at most alpha0: a material distended past it keeps c_e).
  double h(double alpha) const {
    return 1.0 + (std::min(alpha, alpha0) - 1.0) * (ce / cs0 - 1.0) / (alpha0 - 1.0);
  }
  // Eq. (2)'s slope a(alpha_p) and its derivative.
  double elasticSlope(double alphaP) const {
    const double hp = h(alphaP);
    return alphaP * alphaP / Ks * (1.0 - 1.0 / (hp * hp));
  }
  double elasticSlopeDerivative(double alphaP) const {
    const double hp = h(alphaP), dh = alphaP < alpha0 ? (ce / cs0 - 1.0) / (alpha0 - 1.0) : 0.0;
    return 2.0 * alphaP / Ks * (1.0 - 1.0 / (hp * hp)) +
           alphaP * alphaP / Ks * 2.0 * dh / (hp * hp * hp);
  }

  // The crush curve alpha_c(P) and its slope.
  double curve(double P) const {
    if (P <= Pe) return alpha0;
    if (P >= Ps) return 1.0;
    if (twoStage && P <= Pt) return alphaT + (alpha0 - alphaT) * std::pow((Pt - P) / (Pt - Pe), nT);
    const double P1 = twoStage ? Pt : Pe, a1 = twoStage ? alphaT : alpha0;
    return 1.0 + (a1 - 1.0) * std::pow((Ps - P) / (Ps - P1), n);
  }
  double slope(double P) const {
    if (P <= Pe || P >= Ps) return 0.0;
    if (twoStage && P <= Pt)
      return -nT * (alpha0 - alphaT) / (Pt - Pe) * std::pow((Pt - P) / (Pt - Pe), nT - 1.0);
    const double P1 = twoStage ? Pt : Pe, a1 = twoStage ? alphaT : alpha0;
    return -n * (a1 - 1.0) / (Ps - P1) * std::pow((Ps - P) / (Ps - P1), n - 1.0);
  }
  // The inverse: the largest pressure on the curve at distension alpha (alpha0: Pe; 1: Ps), past
  // which a material at alpha compacts, and its slope dP_c/dalpha (-infinity at 1 for n > 1).
  double crushPressure(double alpha) const {
    if (alpha >= alpha0) return Pe;
    if (alpha <= 1.0) return Ps;
    if (twoStage && alpha >= alphaT)
      return Pt - (Pt - Pe) * std::pow((alpha - alphaT) / (alpha0 - alphaT), 1.0 / nT);
    const double P1 = twoStage ? Pt : Pe, a1 = twoStage ? alphaT : alpha0;
    return Ps - (Ps - P1) * std::pow((alpha - 1.0) / (a1 - 1.0), 1.0 / n);
  }
  double crushSlope(double alpha) const {
    if (alpha >= alpha0) return 0.0;
    if (alpha <= 1.0) return -std::numeric_limits<double>::infinity();
    if (twoStage && alpha >= alphaT)
      return -(Pt - Pe) / (nT * (alpha - alphaT)) *
             std::pow((alpha - alphaT) / (alpha0 - alphaT), 1.0 / nT);
    const double P1 = twoStage ? Pt : Pe, a1 = twoStage ? alphaT : alpha0;
    return -(Ps - P1) / (n * (alpha - 1.0)) * std::pow((alpha - 1.0) / (a1 - 1.0), 1.0 / n);
  }
};

struct PorousState {
  double alpha = 1.0, p = 0.0, cs = 0.0;
  double alphaP = 1.0; // the plastic distension (alpha without elastic distension)
  int iterations = 0;  // EOS evaluations of the solve
};

// Eq. (2)'s elastic state at the plastic distension alphaP: the root of H(alpha) = alpha - alpha_p
// - a P(alpha), H' = 1 - a dP/dalpha >= 1 where dP/dalpha > 0 (a <= 0), by Newton from `alpha`.
// Updates alpha, the EOS state s and P; returns the EOS evaluations it took.
template <class E>
int elasticState(const PAlpha& m, const E& eos, double rho, double e, double alphaP, double& alpha,
                 EosState& s, double& P) {
  const double a = m.elasticSlope(alphaP);
  int evaluations = 0;
  for (int k = 0; k < PAlpha::kMaxIterations; ++k) {
    const double H = alpha - alphaP - a * P;
    const double dH = 1.0 - a * (rho * eos.dpdrho(alpha * rho, e) - P) / alpha;
    const double next = std::max(1.0, alpha - H / (std::isfinite(dH) && dH >= 0.5 ? dH : 1.0));
    const double step = std::abs(next - alpha);
    alpha = next;
    s = eos.evaluate(alpha * rho, e);
    ++evaluations;
    P = s.p / alpha;
    if (step < PAlpha::kTolerance) break;
  }
  return evaluations;
}

// The bulk state that advances no history: at the distension alpha, or with elastic distension
// at Eq. (2)'s alpha for the plastic part alphaP (reversible; from alpha as the first guess), so
// that density changes between two updates meet the porous material's stiffness, not the
// matrix's.
template <class E>
PorousState porousState(const PAlpha& m, const E& eos, double rho, double e, double alpha,
                        double alphaP) {
  EosState s = eos.evaluate(alpha * rho, e);
  double P = s.p / alpha;
  int evaluations = 1;
  if (m.elastic() && alphaP > 1.0) evaluations += elasticState(m, eos, rho, e, alphaP, alpha, s, P);
  return {alpha, P, m.elastic() ? s.cs * m.h(alpha) : s.cs, m.elastic() ? alphaP : alpha,
          evaluations};
}
template <class E>
PorousState porousState(const PAlpha& m, const E& eos, double rho, double e, double alpha) {
  return porousState(m, eos, rho, e, alpha, alpha);
}

// Eq. (1) (and Eq. (2) with c_e) from the plastic distension alpha_p_old at the bulk density rho
// and energy e.
template <class E>
PorousState compact(const PAlpha& m, const E& eos, double rho, double e, double alphaOld) {
  PorousState out;
  double alpha = alphaOld;
  EosState s = eos.evaluate(alpha * rho, e);
  out.iterations = 1;
  double P = s.p / alpha;
  // Eq. (2)'s elastic trial at alpha_p_old.
  if (m.elastic() && alphaOld > 1.0)
    out.iterations += elasticState(m, eos, rho, e, alphaOld, alpha, s, P);
  double x = alphaOld; // the plastic distension
  double G = P - m.crushPressure(x);
  if (alphaOld > 1.0 && G > 0.0) { // compaction: the root of G in [1, alpha_p_old)
    // Eq. (2) on the crush curve: alpha(x) = x + a(x) P_c(x) (alpha = x without c_e).
    const auto alphaOf = [&](double xp) {
      return m.elastic() ? std::max(1.0, xp + m.elasticSlope(xp) * m.crushPressure(xp)) : xp;
    };
    alpha = alphaOf(x);
    if (m.elastic()) {
      s = eos.evaluate(alpha * rho, e);
      ++out.iterations;
      P = s.p / alpha, G = P - m.crushPressure(x);
    }
    double a = 1.0, b = x, Gold = G;
    bool triedOne = false; // Newton past 1: try full compaction once (the strong shock's case)
    for (int k = 0; k < PAlpha::kMaxIterations; ++k) {
      // dG/dx = dP/dalpha dalpha/dx - P_c'(x), dP/dalpha = (rho dP_eos/drho_s - P) / alpha,
      // dalpha/dx = 1 + a' P_c + a P_c' (1 without c_e).
      const double dPdalpha = (rho * eos.dpdrho(alpha * rho, e) - P) / alpha;
      const double dalpha = m.elastic() ? 1.0 + m.elasticSlopeDerivative(x) * m.crushPressure(x) +
                                              m.elasticSlope(x) * m.crushSlope(x)
                                        : 1.0;
      const double dG = dPdalpha * dalpha - m.crushSlope(x);
      const double newton = x - G / dG;
      // Safe: bisect when Newton leaves the bracket or the last step did not halve |G|.
      // (At x = 1 the slope of P_c is infinite for n > 1: bisect.)
      const bool progress = std::isfinite(dG) && (k == 0 || std::abs(G) <= 0.5 * std::abs(Gold));
      double next = newton >= a && newton <= b && progress ? newton : 0.5 * (a + b);
      if (newton < 1.0 && !triedOne) next = 1.0, triedOne = true;
      const double step = std::abs(next - x);
      x = next;
      alpha = alphaOf(x);
      s = eos.evaluate(alpha * rho, e);
      ++out.iterations;
      Gold = G;
      P = s.p / alpha, G = P - m.crushPressure(x);
      if (x == 1.0 && G >= 0.0) break; // fully compacted (P >= Ps)
      (G > 0.0 ? b : a) = x;
      if (G == 0.0 || step < PAlpha::kTolerance || b - a < PAlpha::kTolerance) break;
    }
  }
  out.alpha = alpha;
  out.alphaP = x;
  out.p = P;
  out.cs = m.elastic() ? s.cs * m.h(alpha) : s.cs;
  return out;
}

} // namespace spall::materials
