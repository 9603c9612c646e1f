#pragma once
// SPH and ASPH as one step list (SphMethod::advance reads top to bottom): kick-drift, material
// update, whether the lists hold, migration, halo, wall images, neighbors, density, kernel
// correction, module hooks, forces, module hooks, kick, EOS refresh, smoothing update, external
// work, checks, rebalance; with time bins the same list a substep, for the particles whose step
// ends there (methods/SphTimeBins.cpp). The physics is in solvers/ and materials/, the parallel
// machinery in parallel/; this file only orders them.
#include "spall/core/Error.hpp"
#include "spall/core/ParticleFields.hpp"
#include "spall/materials/MaterialUpdate.hpp"
#include "spall/methods/Method.hpp"
#include "spall/methods/MethodSetup.hpp"
#include "spall/methods/Module.hpp"
#include "spall/methods/ParticleMethod.hpp"
#include "spall/neighbors/NeighborList.hpp"
#include "spall/neighbors/VerletList.hpp"
#include "spall/parallel/Decomposition.hpp"
#include "spall/parallel/HaloExchange.hpp"
#include "spall/parallel/Mpi.hpp"
#include "spall/solvers/Boundaries.hpp"
#include "spall/solvers/SphSolver.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace spall::methods {

template <int Dim> class SphMethod final : public ParticleMethod<Dim> {
public:
  // The store's fields are registered (by `modules`) before the method is made.
  SphMethod(const parallel::MpiContext& mpi, MethodSetup setup, materials::MaterialUpdate materials,
            std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
            const ParticleFields<Dim>& f, Field<std::int32_t> cost,
            parallel::Decomposition<Dim>& decomposition);

  void start(const RunStart& run) override;
  void evaluate(std::int64_t step, double time) override;
  double advance(double dt, std::int64_t step, double time) override;
  // With time bins, the step of the slowest bin: the finest step 2^K (methods/SphTimeBins.cpp).
  double stableTimeStep(double floor, std::int64_t step, double time) override;
  double support() const override { return solver_->support(); }
  std::vector<MemoryPart> memoryParts() const override {
    return {{"neighbor_lists", neighbors_.bytes() + verlet_.bytes() + this->cellGridBytes()},
            {"halo", this->haloBytes()},
            {"solver_scratch", solver_->scratchBytes() + allocatedBytes(reach_, boxReach_) +
                                   boundaries_.bytes() + this->loadBytes()}};
  }

private:
  using Base = ParticleMethod<Dim>;
  using Base::bookExternal, Base::checkFinite, Base::externalLoad, Base::materialFields,
      Base::balance;
  using Base::mpi_, Base::materials_, Base::modules_, Base::s_, Base::f_, Base::cost_,
      Base::decomposition_, Base::halo_, Base::grid_, Base::stats_, Base::external_;

  std::pair<double, std::size_t> localTimeStep() const override {
    return solver_->stableTimeStep();
  }
  void exchangeHalo() override;
  void kickDrift(double dt);
  void kick(double dt);
  template <class Half> void kickRows(const EvaluatedRows& rows, Half half);
  // Time bins (methods/SphTimeBins.cpp): the step as 2^K substeps of the finest bin's.
  double advanceInBins(double dt, std::int64_t step, double time);
  void substep(double delta, std::int32_t s, std::int64_t step, double time);
  void predictDensity(double delta, std::int32_t s);
  void selectActive(std::int32_t s);
  void keepPredictingRates();
  void assignBins();
  void kickActive(double delta, std::int32_t s);
  bool rebinActive(double delta, std::int32_t s, int K);
  void wakeNeighbors(double delta, std::int32_t s);
  void measureApproach();
  void refreshBins();
  void countWork(int K);
  bool listsStale(bool wrapped); // wrapped: this step wrapped or folded some particle
  void buildLists();
  void findNeighbors(std::int64_t step);
  std::span<const Tensor<Dim>> anisotropicH() const;
  void densityPass();
  void kernelCorrection();
  void rates(std::int64_t step, double time); // evaluate() without the external power
  void forces(double time);

  MethodSetup setup_;
  std::unique_ptr<solvers::Solver<Dim>> solver_;
  solvers::Boundaries<Dim> boundaries_;
  // Derived from the field flags: what ghosts receive when made, and again after the density
  // pass; the kernel correction, sent on its own.
  std::vector<std::size_t> haloFields_, refreshFields_, correctionFields_;
  neighbors::NeighborList neighbors_; // the step's, without a skin
  neighbors::VerletList<Dim> verlet_; // the wide list (the step's rows in it) and when to search
  // The step's lists: a search's (skin 0) or the wide list's rows filtered for the step.
  const neighbors::NeighborList& lists() const {
    return verlet_.skin() > 0.0 ? verlet_.wide() : neighbors_;
  }
  std::uint64_t builtLayout_ = 0; // the store's rows when the lists were searched
  bool rebuild_ = true;
  std::vector<double> reach_;
  std::vector<Vec<Dim>> boxReach_; // ASPH: the supports' bounding boxes
  // Time bins: the substep's active rows (all of them outside a substep: allActive_), each
  // row's own stable step and its approach's, and its next bin (scratch).
  std::vector<std::uint32_t> active_;
  bool allActive_ = true;
  std::vector<double> ownStep_, approach_; // each row's own step; its approach's (measureApproach)
  std::vector<std::int32_t> nextBin_;
};

} // namespace spall::methods
