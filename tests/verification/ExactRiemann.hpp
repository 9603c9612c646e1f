#pragma once
// The exact solution of the Riemann problem of an ideal gas (Toro, "Riemann Solvers and
// Numerical Methods for Fluid Dynamics", 3rd ed., ch. 4: the pressure function of Eqs. 4.5-4.9
// solved by Newton's method, then sampled in x/t, Sec. 4.5). Test code, written for the tests.
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace spall::verification {

struct GasState {
  double rho, u, p;
};

class ExactRiemann {
public:
  ExactRiemann(GasState left, GasState right, double gamma) : L_(left), R_(right), g_(gamma) {
    cL_ = std::sqrt(g_ * L_.p / L_.rho);
    cR_ = std::sqrt(g_ * R_.p / R_.rho);
    if (2.0 / (g_ - 1.0) * (cL_ + cR_) <= R_.u - L_.u)
      throw std::invalid_argument("vacuum is generated");
    // Two-rarefaction guess (Toro Eq. 4.46), then Newton on f(p) = fL + fR + du.
    const double z = (g_ - 1.0) / (2.0 * g_);
    double p = std::pow((cL_ + cR_ - 0.5 * (g_ - 1.0) * (R_.u - L_.u)) /
                            (cL_ / std::pow(L_.p, z) + cR_ / std::pow(R_.p, z)),
                        1.0 / z);
    for (int it = 0; it < 100; ++it) {
      double fL, dL, fR, dR;
      f(p, L_, cL_, fL, dL);
      f(p, R_, cR_, fR, dR);
      const double pn = std::max(1e-14, p - (fL + fR + R_.u - L_.u) / (dL + dR));
      const double change = 2.0 * std::abs(pn - p) / (pn + p);
      p = pn;
      if (change < 1e-14) break;
    }
    pStar = p;
    double fL, dL, fR, dR;
    f(p, L_, cL_, fL, dL);
    f(p, R_, cR_, fR, dR);
    uStar = 0.5 * (L_.u + R_.u) + 0.5 * (fR - fL);
  }

  double pStar = 0.0, uStar = 0.0;

  // The state at x/t = s (Toro Sec. 4.5).
  GasState sample(double s) const {
    const double g = g_;
    if (s <= uStar) {
      if (pStar > L_.p) { // left shock
        const double pr = pStar / L_.p;
        const double S = L_.u - cL_ * std::sqrt((g + 1) / (2 * g) * pr + (g - 1) / (2 * g));
        if (s <= S) return L_;
        return {L_.rho * (pr + (g - 1) / (g + 1)) / ((g - 1) / (g + 1) * pr + 1), uStar, pStar};
      }
      const double head = L_.u - cL_;
      const double cStar = cL_ * std::pow(pStar / L_.p, (g - 1) / (2 * g));
      const double tail = uStar - cStar;
      if (s <= head) return L_;
      if (s >= tail) return {L_.rho * std::pow(pStar / L_.p, 1 / g), uStar, pStar};
      const double c = 2 / (g + 1) * (cL_ + (g - 1) / 2 * (L_.u - s));
      const double u = 2 / (g + 1) * (cL_ + (g - 1) / 2 * L_.u + s);
      const double rho = L_.rho * std::pow(c / cL_, 2 / (g - 1));
      return {rho, u, L_.p * std::pow(c / cL_, 2 * g / (g - 1))};
    }
    if (pStar > R_.p) { // right shock
      const double pr = pStar / R_.p;
      const double S = R_.u + cR_ * std::sqrt((g + 1) / (2 * g) * pr + (g - 1) / (2 * g));
      if (s >= S) return R_;
      return {R_.rho * (pr + (g - 1) / (g + 1)) / ((g - 1) / (g + 1) * pr + 1), uStar, pStar};
    }
    const double head = R_.u + cR_;
    const double cStar = cR_ * std::pow(pStar / R_.p, (g - 1) / (2 * g));
    const double tail = uStar + cStar;
    if (s >= head) return R_;
    if (s <= tail) return {R_.rho * std::pow(pStar / R_.p, 1 / g), uStar, pStar};
    const double c = 2 / (g + 1) * (cR_ - (g - 1) / 2 * (R_.u - s));
    const double u = 2 / (g + 1) * (-cR_ + (g - 1) / 2 * R_.u + s);
    const double rho = R_.rho * std::pow(c / cR_, 2 / (g - 1));
    return {rho, u, R_.p * std::pow(c / cR_, 2 * g / (g - 1))};
  }

private:
  // Toro Eqs. 4.6-4.7 and their derivatives.
  void f(double p, const GasState& K, double c, double& value, double& deriv) const {
    const double g = g_;
    if (p > K.p) {
      const double A = 2 / ((g + 1) * K.rho), B = (g - 1) / (g + 1) * K.p;
      const double q = std::sqrt(A / (p + B));
      value = (p - K.p) * q;
      deriv = q * (1 - 0.5 * (p - K.p) / (B + p));
    } else {
      const double pr = p / K.p;
      value = 2 * c / (g - 1) * (std::pow(pr, (g - 1) / (2 * g)) - 1);
      deriv = 1 / (K.rho * c) * std::pow(pr, -(g + 1) / (2 * g));
    }
  }

  GasState L_, R_;
  double g_, cL_ = 0, cR_ = 0;
};

} // namespace spall::verification
