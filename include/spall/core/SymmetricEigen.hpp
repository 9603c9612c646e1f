#pragma once
// Eigen-decomposition of a small symmetric tensor, eigenvalues ascending with their unit
// eigenvectors as columns (Eigen's convention). In 2D a closed form: the ASPH update takes three
// per particle per step, and Eigen's general direct solver (scaling, branches) cost more than the
// whole smoothing update around it. 1D and 3D use Eigen's direct solver.
#include "spall/core/Types.hpp"

#include <cmath>

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
    const double a = M(0, 0), b = 0.5 * (M(0, 1) + M(1, 0)), c = M(1, 1);
    const double mean = 0.5 * (a + c), rad = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
    out.values = Vec<2>(mean - rad, mean + rad);
    // (b, l1 - a) and (l1 - c, b) both point along the eigenvector of l1; the longer one is the
    // better conditioned (they differ when b is small).
    const double l1 = mean + rad;
    Vec<2> u(b, l1 - a), w(l1 - c, b);
    const Vec<2>& e = u.squaredNorm() >= w.squaredNorm() ? u : w;
    const double n2 = e.squaredNorm();
    const Vec<2> e1 = n2 > 0.0 ? Vec<2>(e / std::sqrt(n2)) : Vec<2>(0.0, 1.0);
    out.vectors << -e1[1], e1[0], e1[0], e1[1];
  } else {
    Eigen::SelfAdjointEigenSolver<Tensor<Dim>> eig;
    eig.computeDirect(M);
    out.values = eig.eigenvalues();
    out.vectors = eig.eigenvectors();
  }
  return out;
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
