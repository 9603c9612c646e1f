// ASPH with H = I/h is SPH (Owen 2010, Sec. II: "ASPH reduces to SPH in the limit of forcing
// H = delta/h"): the same disordered particles, with h varying from particle to particle, give
// the same density, rates and kernel sums through both instantiations, to round-off.
#include "spall/solvers/SphSolver.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace spall;

namespace {

struct Particles {
  ParticleStore store;
  solvers::SphFields<2> f;
  neighbors::CellGrid<2> grid;
  neighbors::NeighborList nl;
  std::unique_ptr<solvers::Solver<2>> solver;

  Particles(const std::string& method, bool solid) {
    f.registerIn(store, false, solid, false, method == "asph");
    const int n = 16;
    store.resizeLocal(static_cast<std::size_t>(n * n));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double dp = 1.0e-3, rho0 = 1000.0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const std::size_t i = static_cast<std::size_t>(a * n + b);
        store[f.id][i] = i;
        store[f.x][i] = Vec<2>{(a + 0.5 + 0.2 * u(rng)) * dp, (b + 0.5 + 0.2 * u(rng)) * dp};
        store[f.v][i] = Vec<2>{u(rng), u(rng)};
        store[f.m][i] = rho0 * dp * dp;
        store[f.rho][i] = rho0 * (1.0 + 0.01 * u(rng));
        store[f.h][i] = 1.5 * dp * (1.0 + 0.1 * u(rng));
        store[f.e][i] = 100.0 * (1.0 + u(rng));
        if (solid) {
          Tensor<3> S = Tensor<3>::Zero();
          S(0, 0) = 1e6 * u(rng), S(1, 1) = 1e6 * u(rng), S(0, 1) = S(1, 0) = 1e6 * u(rng);
          S(2, 2) = -S(0, 0) - S(1, 1);
          store[f.S][i] = S;
        }
        if (f.anisotropic()) store[f.H][i] = Tensor<2>::Identity() / store[f.h][i];
      }
    SolverConfig cfg;
    cfg.method = method;
    cfg.artificial_stress.enabled = solid;
    std::vector<std::optional<materials::Strength>> strength(1);
    if (solid) strength[0] = materials::Strength{materials::Elastic{1.0e8}};
    solver = solvers::makeSolver<2>({cfg, {materials::LinearEos{1.0e9}}, strength}, store, f);
    // Each through its own search: spheres for SPH, the ellipses |H x| < support for ASPH.
    if (f.anisotropic())
      neighbors::buildNeighborList<2>(store[f.x], store[f.h],
                                      std::span<const Tensor<2>>(store[f.H]), store.localCount(),
                                      solver->support(), grid, nl);
    else
      neighbors::buildNeighborList<2>(store[f.x], store[f.h], store.localCount(), solver->support(),
                                      grid, nl);
    solver->equationOfState();
    solver->computeRates(nl);
  }
};

void expectSame(bool solid) {
  Particles sph("sph", solid), asph("asph", solid);
  ASSERT_TRUE(asph.f.anisotropic());
  double aScale = 0.0, eScale = 0.0, rScale = 0.0;
  for (std::size_t i = 0; i < sph.store.localCount(); ++i) {
    aScale = std::max(aScale, sph.store[sph.f.a][i].norm());
    eScale = std::max(eScale, std::abs(sph.store[sph.f.dedt][i]));
    rScale = std::max(rScale, std::abs(sph.store[sph.f.drhodt][i]));
  }
  for (std::size_t i = 0; i < sph.store.localCount(); ++i) {
    EXPECT_LT((sph.store[sph.f.a][i] - asph.store[asph.f.a][i]).norm(), 1e-12 * aScale) << i;
    EXPECT_NEAR(sph.store[sph.f.dedt][i], asph.store[asph.f.dedt][i], 1e-12 * eScale) << i;
    EXPECT_NEAR(sph.store[sph.f.drhodt][i], asph.store[asph.f.drhodt][i], 1e-12 * rScale) << i;
    EXPECT_NEAR(sph.store[sph.f.psi0][i], asph.store[asph.f.psi0][i],
                1e-12 * sph.store[sph.f.psi0][i]);
    EXPECT_NEAR(sph.solver->nodesPerH(i), asph.solver->nodesPerH(i), 1e-9);
  }
  const auto dtS = sph.solver->stableTimeStep(), dtA = asph.solver->stableTimeStep();
  EXPECT_NEAR(dtS.first, dtA.first, 1e-12 * dtS.first);
  EXPECT_EQ(dtS.second, dtA.second);
  // The summation density too.
  sph.solver->computeDensity(sph.nl);
  asph.solver->computeDensity(asph.nl);
  for (std::size_t i = 0; i < sph.store.localCount(); ++i)
    EXPECT_NEAR(sph.store[sph.f.rho][i], asph.store[asph.f.rho][i], 1e-12 * 1000.0);
}

} // namespace

TEST(Asph, ReducesToSphForRoundTensorsHydro) {
  expectSame(false);
}

// With strength and the artificial stress: the deviatoric, velocity-gradient and artificial
// stress terms see the same gradients and the same mean normalised distance.
TEST(Asph, ReducesToSphForRoundTensorsSolid) {
  expectSame(true);
}
