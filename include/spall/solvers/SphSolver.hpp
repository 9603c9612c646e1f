#pragma once
// The rank-local SPH update: density (summation or continuity), equation of state, momentum and
// energy rates with artificial viscosity, Owen's ideal-h smoothing update and the stable time
// step. No MPI and no files here: the run loop supplies ghosts and reduces the time step.
#include "spall/core/ParticleStore.hpp"
#include "spall/io/Deck.hpp"
#include "spall/kernels/Kernels.hpp"
#include "spall/kernels/PsiTable.hpp"
#include "spall/materials/Eos.hpp"
#include "spall/materials/Strength.hpp"
#include "spall/neighbors/NeighborList.hpp"
#include "spall/solvers/SphFields.hpp"

#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace spall::solvers {

// What the run loop sees of a solver: one virtual call per phase per step, never per particle.
template <int Dim> class Solver {
public:
  virtual ~Solver() = default;
  virtual double support() const = 0;
  virtual bool usesSummationDensity() const = 0;
  // rho_i from the kernel sum (Lam et al. 2001, Eq. 18, or Eq. 25 normalised); owned particles.
  virtual void computeDensity(const neighbors::NeighborList& nl) = 0;
  // p, cs from the material EOS, owned particles.
  virtual void equationOfState() = 0;
  // a, de/dt, drho/dt, and the sums for h and dt; owned particles.
  virtual void computeRates(const neighbors::NeighborList& nl) = 0;
  // Owen (2010) Eqs. 1-3: relax h towards the target nodes per smoothing scale.
  virtual void updateSmoothing() = 0;
  // The local stable time step (the run loop takes the global minimum) and the owned particle
  // that sets it.
  virtual std::pair<double, std::size_t> stableTimeStep() const = 0;
  // The effective nodes per h measured by the last computeRates, for diagnostics.
  virtual double nodesPerH(std::size_t i) const = 0;
  // Advances the deviatoric stress (and plastic strain, temperature) of the particles whose
  // material has strength over dt with the velocity gradient of the last force evaluation.
  virtual void updateStrength(double dt) = 0;
  // The corrected kernel gradient (velocity_gradient = "corrected"): B_i of the owned particles,
  // which the force loop then needs of the ghosts too.
  virtual bool correctsKernel() const = 0;
  virtual void computeKernelCorrection(const neighbors::NeighborList& nl) = 0;
};

struct SolverSetup {
  SolverConfig config;
  std::vector<materials::Eos> eos;                          // by material index
  std::vector<std::optional<materials::Strength>> strength; // by material index; none: fluid
};

// Picks the kernel instantiation once, from the deck.
template <int Dim>
std::unique_ptr<Solver<Dim>> makeSolver(const SolverSetup& setup, ParticleStore& store,
                                        const SphFields<Dim>& f);

} // namespace spall::solvers
