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

// Mie-Gruneisen with a linear Us-up Hugoniot, in the form of Lam, Shen & Gong (2001), Eqs. 4-6:
//   p = (1 - Gamma0 eta / 2) p_H(eta) + Gamma0 rho0 (1 + eta) e,   eta = rho/rho0 - 1   (Eq. 4, 7)
//   p_H = a0 eta + b0 eta^2 + c0 eta^3,  a0 = rho0 C0^2,  b0 = a0 [1 + 2(S-1)],
//   c0 = a0 [2(S-1) + 3(S-1)^2]                                                       (Eq. 5, 6)
// In tension (eta < 0) the Hugoniot terms beyond the linear one are dropped, the usual practice
// for this fit (the cubic is a compression fit and turns over in expansion).
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
  EosState evaluate(double rho, double e) const {
    const double eta = rho / rho0 - 1.0;
    double pH, dpH;
    hugoniot(eta, pH, dpH);
    const double p = (1.0 - 0.5 * Gamma0 * eta) * pH + Gamma0 * rho * e;
    // cs^2 = (dp/drho)_e + (p / rho^2) (dp/de)_rho, with (dp/de)_rho = Gamma0 rho.
    const double dpdrho_e =
        ((1.0 - 0.5 * Gamma0 * eta) * dpH - 0.5 * Gamma0 * pH) / rho0 + Gamma0 * e;
    double cs2 = dpdrho_e + Gamma0 * p / rho;
    // Deep in tension the fit can give cs^2 <= 0; keep a floor so the CFL limit stays finite.
    cs2 = std::max(cs2, 1.0e-2 * C0 * C0);
    return {p, std::sqrt(cs2)};
  }
  double dpdrho(double rho, double e) const {
    const double eta = rho / rho0 - 1.0;
    double pH, dpH;
    hugoniot(eta, pH, dpH);
    return ((1.0 - 0.5 * Gamma0 * eta) * dpH - 0.5 * Gamma0 * pH) / rho0 + Gamma0 * e;
  }
  std::optional<double> energyForPressure(double rho, double p) const {
    const double eta = rho / rho0 - 1.0;
    double pH, dpH;
    hugoniot(eta, pH, dpH);
    return (p - (1.0 - 0.5 * Gamma0 * eta) * pH) / (Gamma0 * rho);
  }
};

using Eos = std::variant<IdealGas, LinearEos, MieGruneisen>;

inline EosState evaluate(const Eos& eos, double rho, double e) {
  return std::visit([&](const auto& m) { return m.evaluate(rho, e); }, eos);
}

} // namespace spall::materials
