#pragma once
// Eigen-decomposition of a small symmetric tensor, eigenvalues ascending with their unit
// eigenvectors as columns (Eigen's convention). In 2D a closed form: the ASPH update takes one or
// two per particle per step, and Eigen's general direct solver (scaling, branches) cost more than
// the whole smoothing update around it. 1D and 3D use Eigen's direct solver.
#include "spall/core/Types.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall {

template <int Dim> struct SymmetricEigen {
  Vec<Dim> values;     // ascending
  Tensor<Dim> vectors; // column k belongs to values[k]
};

template <int Dim> SymmetricEigen<Dim> symmetricEigen(const Tensor<Dim>& M) {
  SymmetricEigen<Dim> out;
  if constexpr (Dim == 1) {
    out.values = M;
    out.vectors.setOnes();
  } else if constexpr (Dim == 2) {
    // Scaled to entries of order one, so that nothing overflows.
    const double b0 = 0.5 * (M(0, 1) + M(1, 0));
    const double scale = std::max({std::abs(M(0, 0)), std::abs(M(1, 1)), std::abs(b0)});
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      out.values = Vec<2>(M(0, 0), M(1, 1));
      out.vectors.setIdentity();
      if (scale == 0.0) return out;
      out.values.setConstant(std::numeric_limits<double>::quiet_NaN());
      return out;
    }
    const double inv = 1.0 / scale;
    const double a = M(0, 0) * inv, b = b0 * inv, c = M(1, 1) * inv;
    const double half = 0.5 * (a - c), mean = 0.5 * (a + c);
    // hypot (slow) only where the squares would underflow: b and a - c both tiny against the
    // diagonal.
    double rad = std::sqrt(half * half + b * b);
    if (rad < 1e-140) rad = std::hypot(half, b);
    out.values = Vec<2>(scale * (mean - rad), scale * (mean + rad));
    // (b, l1 - a) and (l1 - c, b) both point along the eigenvector of l1 = mean + rad; written
    // as (b, rad - half) and (rad + half, b) so that the longer one, the better conditioned,
    // carries no cancellation (nearly equal eigenvalues keep accurate vectors).
    const Vec<2> u(b, rad - half), w(rad + half, b);
    const Vec<2>& e = u.cwiseAbs().maxCoeff() >= w.cwiseAbs().maxCoeff() ? u : w;
    double n = std::sqrt(e[0] * e[0] + e[1] * e[1]);
    if (n < 1e-140) n = std::hypot(e[0], e[1]);
    const Vec<2> e1 = n > 0.0 ? Vec<2>(e / n) : Vec<2>(0.0, 1.0);
    out.vectors << -e1[1], e1[0], e1[0], e1[1];
  } else {
    Eigen::SelfAdjointEigenSolver<Tensor<Dim>> eig;
    eig.computeDirect(M);
    out.values = eig.eigenvalues();
    out.vectors = eig.eigenvectors();
  }
  return out;
}

// The eigenvalues alone, ascending.
template <int Dim> Vec<Dim> symmetricEigenvalues(const Tensor<Dim>& M) {
  if constexpr (Dim == 2) {
    const double b0 = 0.5 * (M(0, 1) + M(1, 0));
    const double scale = std::max({std::abs(M(0, 0)), std::abs(M(1, 1)), std::abs(b0)});
    if (!(scale > 0.0) || !std::isfinite(scale)) return symmetricEigen<2>(M).values;
    const double inv = 1.0 / scale;
    const double half = 0.5 * (M(0, 0) - M(1, 1)) * inv, mean = 0.5 * (M(0, 0) + M(1, 1)) * inv;
    const double b = b0 * inv, rad = std::sqrt(half * half + b * b);
    return Vec<2>(scale * (mean - rad), scale * (mean + rad));
  } else if constexpr (Dim == 1) {
    return M;
  } else {
    Eigen::SelfAdjointEigenSolver<Tensor<Dim>> eig;
    eig.computeDirect(M, Eigen::EigenvaluesOnly);
    return eig.eigenvalues();
  }
}

// The largest eigenvalue alone.
template <int Dim> double largestEigenvalue(const Tensor<Dim>& M) {
  if constexpr (Dim == 1) {
    return M(0, 0);
  } else if constexpr (Dim == 2) {
    const double b = 0.5 * (M(0, 1) + M(1, 0));
    return 0.5 * (M(0, 0) + M(1, 1)) +
           std::sqrt(0.25 * (M(0, 0) - M(1, 1)) * (M(0, 0) - M(1, 1)) + b * b);
  } else {
    Eigen::SelfAdjointEigenSolver<Tensor<Dim>> eig;
    eig.computeDirect(M, Eigen::EigenvaluesOnly);
    return eig.eigenvalues()[Dim - 1];
  }
}

} // namespace spall
