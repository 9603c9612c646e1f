#pragma once
// The fixture of the solver unit tests: an n x n square lattice of 2D particles (spacing 1 mm,
// water-like density, h = 1.5 spacings), optionally disordered, and a solver evaluated on it
// (a linear EOS, an elastic solid where asked; the neighbor search the method uses, the kernel
// correction where enabled, the rates).
#include "spall/materials/MaterialUpdate.hpp"
#include "spall/solvers/SphSolver.hpp"
#include "unit/FieldGroups.hpp"

#include <limits>
#include <memory>
#include <random>

namespace spall::fixtures {

struct SolverLattice {
  static constexpr double dp = 1.0e-3, rho0 = 1000.0;
  ParticleStore store;
  ParticleFields<2> f;
  neighbors::CellGrid<2> grid;
  neighbors::NeighborList nl;
  std::unique_ptr<solvers::Solver<2>> solver;

  // The lattice at rest (or moving with v = G x), with the fields the configuration needs.
  // damage: the solid's failed particles (damage 1) carry no tension (the damaged-pair rule).
  SolverLattice(int n, const SolverConfig& cfg, bool solid, const Tensor<2>& G = Tensor<2>::Zero(),
                bool damage = false)
      : cfg_(cfg), solid_(solid), damage_(damage) {
    registerFields(store, f,
                   {.strength = solid,
                    .corrected = solid && cfg.velocity_gradient == VelocityGradient::Corrected,
                    .asph = cfg.method == SolverMethod::Asph,
                    .damage = damage});
    store.resizeLocal(static_cast<std::size_t>(n * n));
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
        // Eigen's default constructor leaves a tensor uninitialised.
        if (solid) store[f.S][i].setZero(), store[f.L][i].setZero();
      }
  }

  // A disordered state: positions, velocities, densities, h, energies and (solids) deviatoric
  // stresses all varying from particle to particle.
  void disorder(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (std::size_t i = 0; i < store.localCount(); ++i) {
      store[f.x][i] += 0.2 * dp * Vec<2>{u(rng), u(rng)};
      store[f.v][i] = Vec<2>{u(rng), u(rng)};
      store[f.rho][i] = rho0 * (1.0 + 0.01 * u(rng));
      store[f.h][i] = 1.5 * dp * (1.0 + 0.1 * u(rng));
      store[f.e][i] = 100.0 * (1.0 + u(rng));
      if (solid_) {
        Tensor<3> S = Tensor<3>::Zero();
        S(0, 0) = 1e6 * u(rng), S(1, 1) = 1e6 * u(rng), S(0, 1) = S(1, 0) = 1e6 * u(rng);
        S(2, 2) = -S(0, 0) - S(1, 1);
        store[f.S][i] = S;
      }
    }
  }

  // The solver, the neighbor list (spheres for SPH, ellipses |H x| < support for ASPH, with round
  // H = I/h), the EOS, the kernel correction where enabled, and the rates. Rows from
  // `firstWallImage` on are a rigid wall's images (solvers::Boundaries), made by the caller.
  void evaluate(std::size_t firstWallImage = std::numeric_limits<std::size_t>::max()) {
    materials::Material water{materials::LinearEos{1.0e9}, std::nullopt};
    if (solid_) water.strength = materials::Strength{materials::Elastic{1.0e8}};
    solver = solvers::makeSolver<2>(
        {cfg_, {solid_}, damage_ ? std::vector<bool>{true} : std::vector<bool>{}}, store, f);
    if (f.anisotropic()) {
      for (std::size_t i = 0; i < store.localCount(); ++i)
        store[f.H][i] = Tensor<2>::Identity() / store[f.h][i];
      neighbors::buildNeighborList<2>(store[f.x], store[f.h],
                                      std::span<const Tensor<2>>(store[f.H]), store.localCount(),
                                      solver->support(), grid, nl);
    } else {
      neighbors::buildNeighborList<2>(store[f.x], store[f.h], store.localCount(), solver->support(),
                                      grid, nl);
    }
    const std::size_t n = store.localCount();
    materials::MaterialUpdate({water}).evaluate({store[f.rho].first(n),
                                                 store[f.e].first(n),
                                                 store[f.material].first(n),
                                                 store[f.p].first(n),
                                                 store[f.cs].first(n),
                                                 {},
                                                 {},
                                                 {},
                                                 {}});
    if (solver->correctsKernel()) solver->computeKernelCorrection(nl);
    solver->computeRates(nl, firstWallImage);
  }

  // What the rates do to the totals: sum m a (zero if momentum is conserved), sum m (v.a + de/dt)
  // (zero if total energy is), and the largest single contributions to each, for tolerances.
  struct Totals {
    Vec<2> momentum = Vec<2>::Zero();
    double power = 0.0, scaleP = 0.0, scaleE = 0.0;
  };
  Totals totals() const {
    Totals t;
    for (std::size_t i = 0; i < store.localCount(); ++i) {
      const double m = store[f.m][i];
      const Vec<2> a = store[f.a][i], v = store[f.v][i];
      t.momentum += m * a;
      t.power += m * (v.dot(a) + store[f.dedt][i]);
      t.scaleP = std::max(t.scaleP, m * a.norm());
      t.scaleE = std::max(t.scaleE, m * std::abs(store[f.dedt][i]));
    }
    return t;
  }

private:
  SolverConfig cfg_;
  bool solid_, damage_;
};

} // namespace spall::fixtures
