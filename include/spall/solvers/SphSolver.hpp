#pragma once
// The rank-local SPH and ASPH update: density (summation), the kernel correction, momentum and
// energy rates with artificial viscosity, Owen's ideal-H smoothing update and the stable time
// step. No MPI, no files and no material models here: the method (methods/SphMethod) supplies
// ghosts, runs the material update and reduces the time step.
#include "spall/core/EvaluatedRows.hpp"
#include "spall/core/ParticleFields.hpp"
#include "spall/neighbors/NeighborList.hpp"
#include "spall/solvers/Config.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace spall::solvers {

// What the method sees of a solver: one virtual call per phase per step, never per particle.
template <int Dim> class Solver {
public:
  virtual ~Solver() = default;
  virtual double support() const = 0;
  virtual bool usesSummationDensity() const = 0;
  // rho_i from the kernel sum (Lam et al. 2001, Eq. 18, or Eq. 25 normalised); owned particles.
  virtual void computeDensity(const neighbors::NeighborList& nl) = 0;
  // The corrected kernel gradient (velocity_gradient = "corrected"): B_i of the owned particles,
  // which the force loop then needs of the ghosts too.
  virtual bool correctsKernel() const = 0;
  virtual void computeKernelCorrection(const neighbors::NeighborList& nl) = 0;
  // a, de/dt, drho/dt (and L for solids), and the sums for h and dt; owned particles. Rows from
  // `firstWallImage` on are images across rigid walls: they carry the mirrored stress, not the
  // artificial viscosity (a wall is not material: its viscosity acted as friction).
  virtual void computeRates(const neighbors::NeighborList& nl, std::size_t firstWallImage) = 0;
  // Owen (2010) Eqs. 1-6: relax h (or H) towards the target nodes per smoothing scale.
  virtual void updateSmoothing() = 0;
  // The local stable time step (the method takes the global minimum) and the owned particle
  // that sets it.
  virtual std::pair<double, std::size_t> stableTimeStep() const = 0;
  // Each owned particle's own stable step, by the criteria of stableTimeStep (time bins).
  virtual void particleTimeSteps(std::span<double> dt) const = 0;
  // Time bins: the owned rows that the density, correction, rates and smoothing passes compute
  // (the particles whose step ends now), in increasing order; the other rows' results stay as
  // they are. nullptr: every owned row.
  void setActiveRows(const std::vector<std::uint32_t>* rows) { active_ = rows; }
  // The effective nodes per h measured by the last computeRates, for diagnostics.
  virtual double nodesPerH(std::size_t i) const = 0;
  // The bytes its per-row scratch holds allocated (summary.json's memory accounting).
  virtual std::size_t scratchBytes() const = 0;

protected:
  // The passes' rows, of n owned ones.
  EvaluatedRows passRows(std::size_t n) const { return {n, active_}; }
  const std::vector<std::uint32_t>* active_ = nullptr;
};

struct SolverSetup {
  SolverConfig config;
  std::vector<bool> solid; // by material index: has strength (artificial stress acts on solids)
  // By material index: a fully damaged particle carries no tension, so that every pair it is in
  // carries compression only (empty: no material has damage).
  std::vector<bool> failedCarriesNoTension = {};
};

// Picks the kernel and stress instantiation once, from the configuration.
template <int Dim>
std::unique_ptr<Solver<Dim>> makeSolver(const SolverSetup& setup, ParticleStore& store,
                                        const ParticleFields<Dim>& f);

} // namespace spall::solvers
