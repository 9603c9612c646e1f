#pragma once
// A symmetric Dim x Dim tensor stored as its upper triangle, row by row: 1, 3 or 6 numbers where a
// full Tensor<Dim> holds 1, 4 or 9. The force loop keeps one to three of these per row, ghosts
// included (S/rho^2, the strain rate, the artificial stress): two thirds of the bytes in 3D. (It
// reads its own row's as full tensors: held as these in the loop, the step took 25% longer.)
// Stored as T (double, or float for scratch that only a sum of pair terms reads); every product
// is computed in double.
#include "spall/core/Types.hpp"

#include <array>

namespace spall {

template <int Dim, class T = double> struct SymTensor {
  static constexpr int kSize = Dim * (Dim + 1) / 2;
  std::array<T, kSize> a{}; // (0,0), (0,1), (0,2), (1,1), (1,2), (2,2) in 3D

  // The place of (r, c), r <= c, in the upper triangle.
  static constexpr int index(int r, int c) { return r * Dim - r * (r - 1) / 2 + (c - r); }

  double operator()(int r, int c) const {
    return static_cast<double>(r <= c ? a[index(r, c)] : a[index(c, r)]);
  }

  // The symmetric part (M + M^T)/2 of a tensor's leading Dim x Dim block.
  template <class M> static SymTensor symmetricPart(const M& m) {
    SymTensor s;
    for (int r = 0; r < Dim; ++r) {
      s.a[static_cast<std::size_t>(index(r, r))] = static_cast<T>(m(r, r));
      for (int c = r + 1; c < Dim; ++c)
        s.a[static_cast<std::size_t>(index(r, c))] = static_cast<T>(0.5 * (m(r, c) + m(c, r)));
    }
    return s;
  }

  SymTensor operator/(double d) const {
    SymTensor s;
    for (int k = 0; k < kSize; ++k)
      s.a[static_cast<std::size_t>(k)] =
          static_cast<T>(static_cast<double>(a[static_cast<std::size_t>(k)]) / d);
    return s;
  }

  static SymTensor zero() { return SymTensor{}; }

  bool nonzero() const {
    for (T x : a)
      if (x != T(0)) return true;
    return false;
  }

  Tensor<Dim> full() const {
    Tensor<Dim> m;
    for (int r = 0; r < Dim; ++r)
      for (int c = 0; c < Dim; ++c) m(r, c) = (*this)(r, c);
    return m;
  }

  // M g, written out (a product that Eigen would not know to be symmetric).
  Vec<Dim> operator*(const Vec<Dim>& g) const {
    const auto a = wide();
    if constexpr (Dim == 1) {
      return Vec<1>(a[0] * g[0]);
    } else if constexpr (Dim == 2) {
      return Vec<2>(a[0] * g[0] + a[1] * g[1], a[1] * g[0] + a[2] * g[1]);
    } else {
      return Vec<3>(a[0] * g[0] + a[1] * g[1] + a[2] * g[2],
                    a[1] * g[0] + a[3] * g[1] + a[4] * g[2],
                    a[2] * g[0] + a[4] * g[1] + a[5] * g[2]);
    }
  }

  // x . M x, written out (an Eigen product would be a call of its own inside the out-of-line pair
  // function that reads it, which 4% of a solid's step once went to).
  double quadraticForm(const Vec<Dim>& x) const {
    const auto a = wide();
    if constexpr (Dim == 1)
      return a[0] * x[0] * x[0];
    else if constexpr (Dim == 2)
      return x[0] * (a[0] * x[0] + 2.0 * a[1] * x[1]) + a[2] * x[1] * x[1];
    else
      return x[0] * (a[0] * x[0] + 2.0 * (a[1] * x[1] + a[2] * x[2])) +
             x[1] * (a[3] * x[1] + 2.0 * a[4] * x[2]) + a[5] * x[2] * x[2];
  }

private:
  // The entries as doubles (a copy the compiler removes where T is double).
  std::array<double, kSize> wide() const {
    std::array<double, kSize> w;
    for (std::size_t k = 0; k < w.size(); ++k) w[k] = static_cast<double>(a[k]);
    return w;
  }
};

} // namespace spall
