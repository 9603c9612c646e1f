#pragma once
// The material point method's shape functions: one axis at a time, the node's weight S and its
// derivative dS/dx for a particle at distance d = x_p - X_I from node I, cell size hc; in Dim
// dimensions the tensor product S = prod_a S(d_a), dS/dx_a = S'(d_a) prod_{b != a} S(d_b).
//
// A particle touches a fixed block of nodes per axis: the tent reaches one cell (2 nodes, from
// floor(xi)), GIMP one cell plus l_p <= hc/2 (3 nodes, from round(xi) - 1), xi = (x - origin)/hc.
// Nodes of the block the support does not reach get S = 0: a regular layout for every particle.
// CPDI's nodes are those of its domain's corners' cells: a list per particle (cpdi()).
#include "spall/core/SymmetricEigen.hpp"
#include "spall/core/Types.hpp"
#include "spall/solvers/Config.hpp"

#include <algorithm>
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
static_assert(kNodesPerAxis<MpmShape::Gimp> == 3);
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

// cpGIMP's box (contiguous-particle GIMP, Wallstedt & Guilkey 2008): the half-widths of the
// point's deformed domain x_p + R xi, xi in [-1, 1]^Dim (R = F l_p0, as CPDI's), along each grid
// axis. l_a = sqrt((R R^T)_aa) is the half-width of the axis-aligned box with the domain's
// second moment along axis a: a stretch lambda_a gives lambda_a l_p0, a rotation keeps l_p0
// (where F's diagonal, the usual choice, shrinks the box of a turned point), a shear lengthens it
// by sqrt(1 + gamma^2). Within half a cell, where GIMP's weights keep the partition of unity and
// linear completeness (its 3 nodes per axis reach no further).
template <int Dim> Vec<Dim> gimpBox(const Tensor<Dim>& R, double hc) {
  Vec<Dim> l;
  for (int a = 0; a < Dim; ++a) l[a] = std::min(R.row(a).norm(), 0.5 * hc);
  return l;
}

// lp: the box's half-width along each axis (uGIMP: l_p on every axis; cpGIMP: gimpBox).
template <MpmShape Shape, int Dim>
Block<Shape, Dim> block(const Vec<Dim>& x, const Vec<Dim>& origin, double hc, const Vec<Dim>& lp) {
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
        wa[static_cast<std::size_t>(k)] = gimp(x[a] - X, hc, lp[a]);
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

// CPDI1 (Sadeghirad, Brannon & Burghardt 2011, Sec. 3): the point's domain is the parallelogram
// (parallelepiped in 3D, a segment in 1D) x_p + R xi, xi in [-1, 1]^Dim, the columns of R its
// half-edge vectors r_i = F r_i^0 (methods/modules/MaterialPoints). Over the domain each tent N_I
// is replaced by its multilinear interpolation from the 2^Dim corners x_c = x_p + R s_c (s_c in
// {-1, 1}^Dim) and averaged:
//   S_Ip = 2^-Dim sum_c N_I(x_c),   grad S_Ip = 2^-Dim R^-T sum_c N_I(x_c) s_c
// (their Eqs. 29-31 in 2D; the mean of d/dxi of the corner's multilinear function is s_c /
// 2^Dim, and x = x_p + R xi turns d/dxi into R^T d/dx). Partition of unity and linear
// completeness hold for any invertible R: the tent's at each corner, and sum_c s_c x_c^T = 2^Dim
// R^T. The nodes are those of the corners' cells, up to 4^Dim; shared ones are merged, in the
// order they first appear (a function of the point alone, as the sums' order must be).
template <int Dim> inline constexpr int kCpdiEntries = 1 << (2 * Dim);

template <int Dim> struct CpdiWeights {
  int count = 0;
  std::array<std::array<std::int64_t, Dim>, kCpdiEntries<Dim>> key{};
  std::array<double, kCpdiEntries<Dim>> S;
  std::array<Vec<Dim>, kCpdiEntries<Dim>> grad;
};

template <int Dim>
CpdiWeights<Dim> cpdi(const Vec<Dim>& x, const Tensor<Dim>& R, const Vec<Dim>& origin, double hc) {
  constexpr int corners = 1 << Dim;
  constexpr double share = 1.0 / corners;
  CpdiWeights<Dim> w;
  for (int c = 0; c < corners; ++c) {
    Vec<Dim> s;
    for (int a = 0; a < Dim; ++a) s[a] = (c >> a) & 1 ? 1.0 : -1.0;
    const Vec<Dim> xc = x + R * s;
    std::array<std::int64_t, Dim> first;
    Vec<Dim> t;
    for (int a = 0; a < Dim; ++a) {
      const double xi = (xc[a] - origin[a]) / hc;
      first[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(std::floor(xi));
      t[a] = xi - static_cast<double>(first[static_cast<std::size_t>(a)]);
    }
    for (int q = 0; q < corners; ++q) {
      double N = 1.0;
      std::array<std::int64_t, Dim> k = first;
      for (int a = 0; a < Dim; ++a) {
        const bool upper = (q >> a) & 1;
        N *= upper ? t[a] : 1.0 - t[a];
        k[static_cast<std::size_t>(a)] += upper ? 1 : 0;
      }
      if (N == 0.0) continue; // a corner on the node's far face: no weight, no slope
      int e = 0;
      while (e < w.count && w.key[static_cast<std::size_t>(e)] != k) ++e;
      const auto se = static_cast<std::size_t>(e);
      if (e == w.count) {
        ++w.count;
        w.key[se] = k;
        w.S[se] = 0.0;
        w.grad[se].setZero(); // (Eigen does not zero on construction)
      }
      w.S[se] += share * N;
      w.grad[se] += (share * N) * s; // in xi; mapped by R^-T below
    }
  }
  const Tensor<Dim> RinvT = R.inverse().transpose();
  for (int e = 0; e < w.count; ++e)
    w.grad[static_cast<std::size_t>(e)] = RinvT * w.grad[static_cast<std::size_t>(e)];
  return w;
}

// CPDI1's weakness under massive shear: F carries the domain into a sliver whose edges are nearly
// parallel (in a rod's penetration: half-widths 12 cells by 1/200 of one), where R^-T amplifies
// the corners' differences without bound, and the velocity gradient then turns the point inside
// out. As Uintah bounds its domains' lengths (Homel's "lcrit"), a domain stretched past
// `longest` along a principal axis, or `aspect` times longer than it is wide, becomes the box of
// the same second moment (int x x^T dV ~ R R^T = U Sigma^2 U^T: R -> U Sigma), its half-widths
// clamped to [min(sigma_max, longest) / aspect, longest]. The weights' domain only: mass,
// volume and stress are the point's. Returns whether it did. A domain turned inside out (det R
// <= 0: its F inverted) is left as it is: the run stops on it, naming the point.
template <int Dim> bool regulariseDomain(Tensor<Dim>& R, double longest, double aspect) {
  if (!(R.determinant() > 0.0)) return false;
  const Tensor<Dim> M = R * R.transpose(); // its eigenvalues: the half-widths squared
  const double trace = M.trace(), det = M.determinant();
  const double a2 = aspect * aspect;
  // Sufficient for sigma_max <= longest and sigma_max / sigma_min <= aspect: sigma_max^2 <=
  // trace, and sigma_max^2 / sigma_min^2 <= trace^Dim / (Dim-1)^(Dim-1) / det (AM-GM over the
  // Dim - 1 largest) -- exact in 2D.
  if (trace <= longest * longest) {
    if constexpr (Dim == 1) return false;
    const double bound = Dim == 2 ? trace * trace / det : trace * trace * trace / (4.0 * det);
    if (det > 0.0 && (Dim == 2 ? bound <= a2 + 2.0 + 1.0 / a2 : bound <= a2)) return false;
  }
  const auto e = symmetricEigen<Dim>(M);
  const double hi = std::sqrt(std::max(e.values[Dim - 1], 0.0));
  const double lo = std::sqrt(std::max(e.values[0], 0.0));
  if (hi <= longest && hi <= aspect * lo) return false;
  const double top = std::min(hi, longest);
  Tensor<Dim> out;
  for (int k = 0; k < Dim; ++k) {
    const double sigma = std::clamp(std::sqrt(std::max(e.values[k], 0.0)), top / aspect, top);
    out.col(k) = sigma * e.vectors.col(k);
  }
  if (out.determinant() < 0.0) out.col(0) = -out.col(0); // the same corners, right-handed
  R = out;
  return true;
}

} // namespace spall::solvers::mpm
