#pragma once
// Equations of state: pure functions of (rho, e) giving pressure p, sound speed cs and the
// isoenergetic derivative dp/drho (the P-alpha porosity model needs the latter). No particles,
// no MPI: the simulation and the single-element driver call the very same code.
#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

namespace spall::materials {

struct EosState {
  double p = 0.0;  // pressure, Pa
  double cs = 0.0; // adiabatic sound speed, m/s
};

// p = (gamma - 1) rho e.
struct IdealGas {
  double gamma = 1.4;

  EosState evaluate(double rho, double e) const {
    const double p = (gamma - 1.0) * rho * e;
    return {p, std::sqrt(std::max(gamma * p / rho, 0.0))};
  }
  double dpdrho(double /*rho*/, double e) const { return (gamma - 1.0) * e; }
  std::optional<double> energyForPressure(double rho, double p) const {
    return p / ((gamma - 1.0) * rho);
  }
};

// p = K (rho/rho0 - 1): a barotropic solid or liquid; e plays no part.
struct LinearEos {
  double rho0 = 1.0;
  double K = 1.0; // bulk modulus

  EosState evaluate(double rho, double /*e*/) const {
    return {K * (rho / rho0 - 1.0), std::sqrt(K / rho0)};
  }
  double dpdrho(double /*rho*/, double /*e*/) const { return K / rho0; }
  std::optional<double> energyForPressure(double, double) const { return std::nullopt; }
};

// Mie-Gruneisen with a linear Us-up Hugoniot referenced to the Hugoniot of Lam, Shen & Gong
// (2001), Eqs. 4-6:
//   p = (1 - Gamma eta / 2) p_H(eta) + Gamma rho e,   eta = rho/rho0 - 1                (Eq. 4)
//   p_H = a0 eta + b0 eta^2 + c0 eta^3,  a0 = rho0 C0^2,  b0 = a0 [1 + 2(S-1)],
//   c0 = a0 [2(S-1) + 3(S-1)^2]                                                       (Eq. 5, 6)
// Lam et al. hold Gamma = Gamma0; then the cold term (1 - Gamma0 eta/2) p_H turns negative past
// rho = (1 + 2/Gamma0) rho0 (about twice the density for metals), and a particle compressed that
// far is pulled in further, without bound (the collapses of tools/stress). In compression this
// code holds Gamma rho = Gamma0 rho0 instead, the usual Mie-Gruneisen assumption (Gamma/V
// constant): the cold factor becomes 1 - Gamma0 eta / (2 (1 + eta)), positive up to rho/rho0 =
// Gamma0/(Gamma0 - 2) (101 for copper; no limit for Gamma0 <= 2), equal to Lam's in value and
// slope at eta = 0 and within Gamma0 eta^2/2 of it (1e-4 relative at 1% compression).
// In tension (eta < 0) Lam's form is kept, and the Hugoniot terms beyond the linear one are
// dropped, the usual practice for this fit (the cubic is a compression fit and turns over in
// expansion).
struct MieGruneisen {
  double rho0 = 1.0;
  double C0 = 1.0;     // bulk sound speed
  double S = 1.0;      // Us-up slope
  double Gamma0 = 1.0; // Gruneisen coefficient

  double a0() const { return rho0 * C0 * C0; }
  double b0() const { return a0() * (1.0 + 2.0 * (S - 1.0)); }
  double c0() const { return a0() * (2.0 * (S - 1.0) + 3.0 * (S - 1.0) * (S - 1.0)); }

  // p_H and dp_H/deta
  void hugoniot(double eta, double& pH, double& dpH) const {
    if (eta > 0.0) {
      pH = eta * (a0() + eta * (b0() + eta * c0()));
      dpH = a0() + eta * (2.0 * b0() + 3.0 * eta * c0());
    } else {
      pH = a0() * eta;
      dpH = a0();
    }
  }
  // The cold factor f(eta) multiplying p_H, its derivative, and Gamma rho (= dp/de at fixed rho).
  void gruneisen(double eta, double& f, double& df, double& gammaRho) const {
    if (eta > 0.0) {
      f = 1.0 - 0.5 * Gamma0 * eta / (1.0 + eta);
      df = -0.5 * Gamma0 / ((1.0 + eta) * (1.0 + eta));
      gammaRho = Gamma0 * rho0;
    } else {
      f = 1.0 - 0.5 * Gamma0 * eta;
      df = -0.5 * Gamma0;
      gammaRho = Gamma0 * rho0 * (1.0 + eta);
    }
  }
  EosState evaluate(double rho, double e) const {
    const double eta = rho / rho0 - 1.0;
    double pH, dpH, f, df, gammaRho;
    hugoniot(eta, pH, dpH);
    gruneisen(eta, f, df, gammaRho);
    const double p = f * pH + gammaRho * e;
    // cs^2 = (dp/drho)_e + (p / rho^2) (dp/de)_rho.
    double cs2 = dpdrho(rho, e) + gammaRho * p / (rho * rho);
    // Deep in tension the fit can give cs^2 <= 0; keep a floor so the CFL limit stays finite.
    cs2 = std::max(cs2, 1.0e-2 * C0 * C0);
    return {p, std::sqrt(cs2)};
  }
  double dpdrho(double rho, double e) const {
    const double eta = rho / rho0 - 1.0;
    double pH, dpH, f, df, gammaRho;
    hugoniot(eta, pH, dpH);
    gruneisen(eta, f, df, gammaRho);
    // d(gamma rho)/drho: 0 in compression (constant), Gamma0 in tension.
    const double dGammaRho = eta > 0.0 ? 0.0 : Gamma0;
    return (f * dpH + df * pH) / rho0 + dGammaRho * e;
  }
  std::optional<double> energyForPressure(double rho, double p) const {
    const double eta = rho / rho0 - 1.0;
    double pH, dpH, f, df, gammaRho;
    hugoniot(eta, pH, dpH);
    gruneisen(eta, f, df, gammaRho);
    return (p - f * pH) / gammaRho;
  }
};

// Tillotson (1962) EOS in the form used for planetary impacts (e.g. Melosh 1989, Sec. 3.5):
//   eta = rho/rho0, mu = eta - 1, w = e/(E0 eta^2) + 1
//   compressed (mu >= 0) and cold expanded (e <= E_iv):
//     p_c = (a + b/w) rho e + A mu + B mu^2
//   hot expanded (e >= E_cv, mu < 0):
//     p_e = a rho e + [b rho e / w + A mu exp(-beta (1/eta - 1))] exp(-alpha (1/eta - 1)^2)
//   in between, p = ((e - E_iv) p_e + (E_cv - e) p_c) / (E_cv - E_iv), so p is continuous in e.
// cs^2 = (dp/drho)_e + p/rho^2 (dp/de)_rho, from the analytic derivatives of each branch, with a
// floor of A/rho0 / 100 (the cold expanded branch can give cs^2 <= 0 in deep tension).
struct Tillotson {
  double rho0 = 1.0;
  double a = 0.5, b = 1.5; // dimensionless
  double A = 1.0, B = 1.0; // Pa
  double alpha = 5.0, beta = 5.0;
  double E0 = 1.0;             // J/kg
  double Eiv = 1.0, Ecv = 2.0; // incipient and complete vaporisation energies, J/kg

  struct Branch {
    double p, dpdrho, dpde;
  };
  Branch compressed(double rho, double e) const {
    const double eta = rho / rho0, mu = eta - 1.0;
    const double w = e / (E0 * eta * eta) + 1.0;
    const double dwdrho = -2.0 * e / (E0 * eta * eta * eta * rho0), dwde = 1.0 / (E0 * eta * eta);
    const double f = a + b / w;
    const double p = f * rho * e + A * mu + B * mu * mu;
    const double dpdrho = f * e - b / (w * w) * dwdrho * rho * e + (A + 2.0 * B * mu) / rho0;
    const double dpde = f * rho - b / (w * w) * dwde * rho * e;
    return {p, dpdrho, dpde};
  }
  Branch expanded(double rho, double e) const {
    const double eta = rho / rho0, mu = eta - 1.0;
    const double w = e / (E0 * eta * eta) + 1.0;
    const double dwdrho = -2.0 * e / (E0 * eta * eta * eta * rho0), dwde = 1.0 / (E0 * eta * eta);
    const double z = 1.0 / eta - 1.0, dzdrho = -rho0 / (rho * rho);
    const double g = std::exp(-alpha * z * z), dgdrho = -2.0 * alpha * z * dzdrho * g;
    const double h = std::exp(-beta * z), dhdrho = -beta * dzdrho * h;
    const double inner = b * rho * e / w + A * mu * h;
    const double dinner_drho =
        b * e / w - b * rho * e / (w * w) * dwdrho + A / rho0 * h + A * mu * dhdrho;
    const double dinner_de = b * rho / w - b * rho * e / (w * w) * dwde;
    const double p = a * rho * e + inner * g;
    return {p, a * e + dinner_drho * g + inner * dgdrho, a * rho + dinner_de * g};
  }
  Branch branch(double rho, double e) const {
    if (rho >= rho0 || e <= Eiv) return compressed(rho, e);
    if (e >= Ecv) return expanded(rho, e);
    const Branch c = compressed(rho, e), x = expanded(rho, e);
    const double span = Ecv - Eiv, wE = (e - Eiv) / span, wC = (Ecv - e) / span;
    return {wE * x.p + wC * c.p, wE * x.dpdrho + wC * c.dpdrho,
            wE * x.dpde + wC * c.dpde + (x.p - c.p) / span};
  }
  EosState evaluate(double rho, double e) const {
    const Branch t = branch(rho, e);
    const double cs2 = std::max(t.dpdrho + t.p / (rho * rho) * t.dpde, 0.01 * A / rho0);
    return {t.p, std::sqrt(cs2)};
  }
  double dpdrho(double rho, double e) const { return branch(rho, e).dpdrho; }
  std::optional<double> energyForPressure(double rho, double p) const {
    // Only the compressed/cold branch is inverted (initial states): p_c is linear-fractional in e
    // there, solved by a few Newton steps from e = 0.
    double e = 0.0;
    for (int k = 0; k < 50; ++k) {
      const Branch c = compressed(rho, e);
      if (c.dpde <= 0.0) return std::nullopt;
      const double de = (p - c.p) / c.dpde;
      e += de;
      if (std::abs(de) <= 1e-14 * std::max(1.0, std::abs(e))) return e;
    }
    return std::nullopt;
  }
};

using Eos = std::variant<IdealGas, LinearEos, MieGruneisen, Tillotson>;

inline EosState evaluate(const Eos& eos, double rho, double e) {
  return std::visit([&](const auto& m) { return m.evaluate(rho, e); }, eos);
}

} // namespace spall::materials
