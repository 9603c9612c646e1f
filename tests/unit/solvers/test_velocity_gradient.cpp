// The velocity gradient of the SPH force loop on a bounded 2D lattice with a linear velocity
// field v = G x: the plain estimate is exact inside and wrong near the free surfaces (the kernel
// is cut off there); the linearly corrected one (Randles & Libersky 1996) is exact everywhere.
#include "spall/solvers/SphSolver.hpp"

#include <gtest/gtest.h>

using namespace spall;

namespace {

struct Lattice {
  ParticleStore store;
  solvers::SphFields<2> f;
  neighbors::CellGrid<2> grid;
  neighbors::NeighborList nl;
  std::unique_ptr<solvers::Solver<2>> solver;

  Lattice(VelocityGradient method, const Tensor<2>& G, int n = 14) {
    f.registerIn(store, false, true);
    store.resizeLocal(static_cast<std::size_t>(n * n));
    const double dp = 1.0e-3, rho0 = 1000.0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const std::size_t i = static_cast<std::size_t>(a * n + b);
        const Vec<2> x{(a + 0.5) * dp, (b + 0.5) * dp};
        store[f.id][i] = i;
        store[f.x][i] = x;
        store[f.v][i] = G * x;
        store[f.m][i] = rho0 * dp * dp;
        store[f.rho][i] = rho0;
        store[f.h][i] = 1.5 * dp;
        store[f.cs][i] = 10.0;
      }
    SolverConfig cfg;
    cfg.velocity_gradient = method;
    solvers::SolverSetup setup{
        cfg, {materials::LinearEos{1.0e9}}, {materials::Strength{materials::Elastic{1.0e8}}}};
    solver = solvers::makeSolver<2>(setup, store, f);
    neighbors::buildNeighborList<2>(store[f.x], store[f.h], store.localCount(), solver->support(),
                                    grid, nl);
    solver->equationOfState();
    solver->computeRates(nl);
  }
  // Largest |L - G| over the particles that are (inner) or are not (surface) two supports away
  // from every edge.
  double worstError(const Tensor<2>& G, bool inner) {
    double worst = 0.0;
    const double dp = 1.0e-3, edge = 14 * dp, margin = 3.0 * dp;
    for (std::size_t i = 0; i < store.localCount(); ++i) {
      const Vec<2> x = store[f.x][i];
      const bool isInner = x.minCoeff() > margin && x.maxCoeff() < edge - margin;
      if (isInner != inner) continue;
      const Tensor<2> L = store[f.L][i].topLeftCorner<2, 2>();
      worst = std::max(worst, (L - G).cwiseAbs().maxCoeff() / G.cwiseAbs().maxCoeff());
    }
    return worst;
  }
};

// A stretch, a shear and a spin together.
Tensor<2> gradient() {
  Tensor<2> G;
  G << 30.0, -12.0, 20.0, -8.0;
  return G;
}

} // namespace

TEST(VelocityGradient, PlainSphIsExactInsideOnlyAndCorrectedEverywhere) {
  const Tensor<2> G = gradient();
  Lattice plain(VelocityGradient::Sph, G), corrected(VelocityGradient::Corrected, G);
  // Inside a uniform lattice both are exact to round-off (sum_j V_j x_ji (x) grad W = I there by
  // symmetry, up to the lattice sum's ~1e-3 deviation of a cubic spline at n_h = 1.5).
  EXPECT_LT(plain.worstError(G, true), 2e-2);
  EXPECT_LT(corrected.worstError(G, true), 1e-10);
  // Near a free surface half the kernel is missing: the plain estimate is off by tens of percent.
  EXPECT_GT(plain.worstError(G, false), 0.2);
  EXPECT_LT(corrected.worstError(G, false), 1e-10);
}
