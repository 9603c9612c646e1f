// ASPH with H = I/h is SPH (Owen 2010, Sec. II: "ASPH reduces to SPH in the limit of forcing
// H = delta/h"): the same disordered particles, with h varying from particle to particle, give
// the same density, rates and kernel sums through both instantiations, to round-off.
#include "SolverLattice.hpp"

#include <gtest/gtest.h>

using namespace spall;

namespace {

// The same disordered particles through SPH or ASPH.
struct Particles : fixtures::SolverLattice {
  Particles(SolverMethod method, bool solid) : SolverLattice(16, config(method, solid), solid) {
    disorder(11);
    evaluate();
  }
  static SolverConfig config(SolverMethod method, bool solid) {
    SolverConfig cfg;
    cfg.method = method;
    cfg.artificial_stress.enabled = solid;
    return cfg;
  }
};

void expectSame(bool solid) {
  Particles sph(SolverMethod::Sph, solid), asph(SolverMethod::Asph, solid);
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
    EXPECT_NEAR(sph.store[sph.f.sumWH][i], asph.store[asph.f.sumWH][i],
                1e-12 * sph.store[sph.f.sumWH][i]);
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
