#pragma once
// Smoothing kernels W(r, h) = sigma_d / h^d * f(q), q = r/h, all with compact support q < 2, so
// that n_h (nodes per smoothing scale, Owen 2010) means the same neighbor count for every kernel.
// Each kernel supplies the dimensionless shape f(q), its derivative df/dq and the normalisation
// sigma_d that makes the volume integral of W one in Dim dimensions.
#include <cmath>
#include <numbers>

namespace spall::kernels {

// Cubic B-spline (Monaghan & Lattanzio 1985; Lam et al. 2001, Eq. 14 in 1D).
template <int Dim> struct CubicSpline {
  static constexpr double support = 2.0;
  static constexpr double sigma() {
    if constexpr (Dim == 1)
      return 2.0 / 3.0;
    else if constexpr (Dim == 2)
      return 10.0 / (7.0 * std::numbers::pi);
    else
      return 1.0 / std::numbers::pi;
  }
  static double f(double q) {
    if (q < 1.0) return 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    if (q < 2.0) {
      const double t = 2.0 - q;
      return 0.25 * t * t * t;
    }
    return 0.0;
  }
  static double df(double q) {
    if (q < 1.0) return q * (-3.0 + 2.25 * q);
    if (q < 2.0) {
      const double t = 2.0 - q;
      return -0.75 * t * t;
    }
    return 0.0;
  }
};

// Wendland C2 (Wendland 1995; Dehnen & Aly 2012), support radius 2h. In 1D the C2 function of
// the 1D family: (1-q/2)^3 (1 + 3q/2).
template <int Dim> struct WendlandC2 {
  static constexpr double support = 2.0;
  static constexpr double sigma() {
    if constexpr (Dim == 1)
      return 5.0 / 8.0;
    else if constexpr (Dim == 2)
      return 7.0 / (4.0 * std::numbers::pi);
    else
      return 21.0 / (16.0 * std::numbers::pi);
  }
  static double f(double q) {
    if (q >= 2.0) return 0.0;
    const double u = 1.0 - 0.5 * q;
    if constexpr (Dim == 1)
      return u * u * u * (1.0 + 1.5 * q);
    else
      return u * u * u * u * (1.0 + 2.0 * q);
  }
  static double df(double q) {
    if (q >= 2.0) return 0.0;
    const double u = 1.0 - 0.5 * q;
    if constexpr (Dim == 1)
      return -3.0 * q * u * u;
    else
      return -5.0 * q * u * u * u;
  }
};

// Wendland C4, support radius 2h. 1D: (1-q/2)^5 (1 + 5q/2 + 2q^2); 2D/3D: (1-q/2)^6 (1 + 3q +
// 35q^2/12).
template <int Dim> struct WendlandC4 {
  static constexpr double support = 2.0;
  static constexpr double sigma() {
    if constexpr (Dim == 1)
      return 3.0 / 4.0;
    else if constexpr (Dim == 2)
      return 9.0 / (4.0 * std::numbers::pi);
    else
      return 495.0 / (256.0 * std::numbers::pi);
  }
  static double f(double q) {
    if (q >= 2.0) return 0.0;
    const double u = 1.0 - 0.5 * q;
    const double u2 = u * u;
    if constexpr (Dim == 1)
      return u2 * u2 * u * (1.0 + 2.5 * q + 2.0 * q * q);
    else
      return u2 * u2 * u2 * (1.0 + 3.0 * q + 35.0 / 12.0 * q * q);
  }
  static double df(double q) {
    if (q >= 2.0) return 0.0;
    const double u = 1.0 - 0.5 * q;
    const double u2 = u * u;
    if constexpr (Dim == 1)
      return -3.5 * q * (1.0 + 2.0 * q) * u2 * u2;
    else
      return -14.0 / 3.0 * q * (1.0 + 2.5 * q) * u2 * u2 * u;
  }
};

// Dimensional helpers shared by every kernel.
template <class K, int Dim> struct Kernel {
  static constexpr double support = K::support;
  // W(r, h)
  static double W(double r, double h) { return K::sigma() * K::f(r / h) / std::pow(h, Dim); }
  // dW/dr (negative inside the support)
  static double dWdr(double r, double h) {
    return K::sigma() * K::df(r / h) / std::pow(h, Dim + 1);
  }
  // Owen (2010), Sec. II-C: W^H(eta) = |dW/deta|, the weight of the ideal-H moments.
  static double WH(double eta) { return K::sigma() * std::abs(K::df(eta)); }
};

} // namespace spall::kernels
