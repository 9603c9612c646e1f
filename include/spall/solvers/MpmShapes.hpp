#pragma once
// The material point method's shape functions: one axis at a time, the node's weight S and its
// derivative dS/dx for a particle at distance d = x_p - X_I from node I, cell size hc; in Dim
// dimensions the tensor product S = prod_a S(d_a), dS/dx_a = S'(d_a) prod_{b != a} S(d_b).
//
// A particle touches a fixed block of nodes per axis: the tent reaches one cell (2 nodes, from
// floor(xi)), uGIMP one cell plus l_p <= hc/2 (3 nodes, from round(xi) - 1), xi = (x - origin)/hc.
// Nodes of the block the support does not reach get S = 0: a regular layout for every particle.
#include "spall/core/Types.hpp"
#include "spall/solvers/Config.hpp"

#include <array>
#include <cmath>
#include <cstdint>

namespace spall::solvers::mpm {

struct Weight {
  double S = 0.0, dS = 0.0;
};

// uGIMP: the tent averaged over the particle's box [x_p - lp, x_p + lp] (Bardenhagen & Kober
// 2004, Eq. 37; lp <= hc/2). C1 in d, so a particle crossing a cell face feels no jump in its
// force (the tent's cell-crossing noise).
inline Weight gimp(double d, double hc, double lp) {
  const double r = std::abs(d);
  const double sign = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
  if (r < lp) return {1.0 - (r * r + lp * lp) / (2.0 * hc * lp), -d / (hc * lp)};
  if (r < hc - lp) return {1.0 - r / hc, -sign / hc};
  if (r < hc + lp) {
    const double q = hc + lp - r;
    return {q * q / (4.0 * hc * lp), -sign * q / (2.0 * hc * lp)};
  }
  return {};
}

template <MpmShape Shape> inline constexpr int kNodesPerAxis = Shape == MpmShape::Linear ? 2 : 3;
template <MpmShape Shape, int Dim>
inline constexpr int kNodesPerParticle =
    Dim == 1 ? kNodesPerAxis<Shape>
             : (Dim == 2 ? kNodesPerAxis<Shape> * kNodesPerAxis<Shape>
                         : kNodesPerAxis<Shape> * kNodesPerAxis<Shape> * kNodesPerAxis<Shape>);

// The first node of a particle's block along one axis, xi = (x - origin)/hc.
template <MpmShape Shape> inline std::int64_t firstNode(double xi) {
  if constexpr (Shape == MpmShape::Linear)
    return static_cast<std::int64_t>(std::floor(xi));
  else
    return static_cast<std::int64_t>(std::floor(xi + 0.5)) - 1;
}

// A particle's block: the first node per axis, and each node's S and grad S in the block's
// order (axis 0 fastest).
template <MpmShape Shape, int Dim> struct Block {
  std::array<std::int64_t, Dim> first{};
  std::array<double, kNodesPerParticle<Shape, Dim>> S{};
  std::array<Vec<Dim>, kNodesPerParticle<Shape, Dim>> grad{};
};

template <MpmShape Shape, int Dim>
Block<Shape, Dim> block(const Vec<Dim>& x, const Vec<Dim>& origin, double hc, double lp) {
  constexpr int n = kNodesPerAxis<Shape>;
  Block<Shape, Dim> b;
  std::array<std::array<Weight, n>, Dim> w;
  for (int a = 0; a < Dim; ++a) {
    const double xi = (x[a] - origin[a]) / hc;
    const std::int64_t first = firstNode<Shape>(xi);
    b.first[static_cast<std::size_t>(a)] = first;
    auto& wa = w[static_cast<std::size_t>(a)];
    if constexpr (Shape == MpmShape::Linear) {
      // The tent within the point's cell (Sulsky, Chen & Schreyer 1994, Eq. 21), its slope the
      // cell's: one-sided on a node, so the gradient stays complete there too.
      (void)lp;
      const double t = xi - static_cast<double>(first);
      wa[0] = {1.0 - t, -1.0 / hc};
      wa[1] = {t, 1.0 / hc};
    } else {
      for (int k = 0; k < n; ++k) {
        const double X = origin[a] + static_cast<double>(first + k) * hc;
        wa[static_cast<std::size_t>(k)] = gimp(x[a] - X, hc, lp);
      }
    }
  }
  for (int q = 0; q < kNodesPerParticle<Shape, Dim>; ++q) {
    std::array<int, Dim> k{};
    for (int a = 0, r = q; a < Dim; ++a, r /= n) k[static_cast<std::size_t>(a)] = r % n;
    double S = 1.0;
    Vec<Dim> g = Vec<Dim>::Ones();
    for (int a = 0; a < Dim; ++a) {
      const Weight& wa = w[static_cast<std::size_t>(a)][static_cast<std::size_t>(k[a])];
      S *= wa.S;
      for (int c = 0; c < Dim; ++c) g[c] *= c == a ? wa.dS : wa.S;
    }
    b.S[static_cast<std::size_t>(q)] = S;
    b.grad[static_cast<std::size_t>(q)] = g;
  }
  return b;
}

// The offset of block entry q from the block's first node, per axis.
template <MpmShape Shape, int Dim> std::array<int, Dim> blockOffset(int q) {
  std::array<int, Dim> k{};
  for (int a = 0, r = q; a < Dim; ++a, r /= kNodesPerAxis<Shape>)
    k[static_cast<std::size_t>(a)] = r % kNodesPerAxis<Shape>;
  return k;
}

} // namespace spall::solvers::mpm
