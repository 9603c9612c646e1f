#pragma once
// SPH and ASPH as one step list (SphMethod::advance reads top to bottom): kick-drift, material
// update, migration, halo, wall images, neighbors, density, kernel correction, module hooks,
// forces, module hooks, kick, EOS refresh, smoothing update, external work, checks, rebalance.
// The physics is in solvers/ and materials/, the parallel machinery in parallel/; this file only
// orders them.
#include "spall/core/Error.hpp"
#include "spall/core/ParticleFields.hpp"
#include "spall/materials/MaterialUpdate.hpp"
#include "spall/methods/Method.hpp"
#include "spall/methods/Module.hpp"
#include "spall/methods/SphSetup.hpp"
#include "spall/neighbors/NeighborList.hpp"
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

template <int Dim> class SphMethod final : public Method<Dim> {
public:
  // The store's fields are registered (by `modules`) before the method is made.
  SphMethod(const parallel::MpiContext& mpi, SphSetup setup, materials::MaterialUpdate materials,
            std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
            const ParticleFields<Dim>& f, Field<std::int32_t> cost,
            parallel::Decomposition<Dim>& decomposition);

  void start(const RunStart& run) override;
  diagnostics::FragmentCatalogue findFragments(double linkLength, double damageThreshold) override;
  void evaluate(std::int64_t step, double time) override;
  void advance(double dt, std::int64_t step, double time) override;
  double stableTimeStep(double floor, std::int64_t step, double time) override;
  ParticleReport timeStepSetter() const override;
  ParticleReport particle(ParticleId id) const override;
  double support() const override { return solver_->support(); }
  double externalWork() const override { return externalWork_; }
  std::array<double, 3> externalImpulse() const override { return externalImpulse_; }
  StepStats& stats() override { return stats_; }
  void save(io::CheckpointState& st) const override;
  void restore(const io::CheckpointState& st) override;
  void addModule(std::unique_ptr<Module<Dim>> module) override {
    module->registerFields(s_, f_);
    modules_.push_back(std::move(module));
  }

private:
  void kickDrift(double dt);
  void kick(double dt);
  void exchangeHalo();
  void findNeighbors(std::int64_t step);
  void densityPass();
  void kernelCorrection();
  void rates(std::int64_t step, double time); // evaluate() without the external power
  void forces(double time);
  ExternalLoad externalLoad(double time) const; // all ranks
  void bookExternal(double dt, const ExternalLoad& now);
  materials::MaterialFields materialFields();
  void checkFinite(std::int64_t step, double time) const;
  // The fields of owned row i that no state can have (non-finite, non-positive density or h):
  // visit(name) for each; badFields joins their names.
  template <class Visit> void forEachBadField(std::size_t i, Visit&& visit) const;
  std::string badFields(std::size_t i) const;
  ParticleId setterId(double dtLocal, double dt, std::size_t which) const;
  bool gather(ParticleReport& fault, ParticleId mine, std::size_t row, std::string& fields) const;
  [[noreturn]] void raise(ParticleReport fault, ParticleId mine, std::size_t row) const;
  void balance(std::int64_t step);
  double canonicalH() const;

  const parallel::MpiContext& mpi_;
  SphSetup setup_;
  materials::MaterialUpdate materials_;
  std::vector<std::unique_ptr<Module<Dim>>> modules_;
  ParticleStore& s_;
  ParticleFields<Dim> f_;
  Field<std::int32_t> cost_;
  parallel::Decomposition<Dim>& decomposition_;
  std::unique_ptr<solvers::Solver<Dim>> solver_;
  solvers::Boundaries<Dim> boundaries_;
  parallel::HaloExchange<Dim> halo_;
  // Derived from the field flags: what ghosts receive when made, and again after the density
  // pass; the kernel correction, sent on its own.
  std::vector<std::size_t> haloFields_, refreshFields_, correctionFields_;
  neighbors::CellGrid<Dim> grid_;
  neighbors::NeighborList neighbors_;
  std::vector<double> reach_;
  std::vector<Vec<Dim>> boxReach_; // ASPH: the supports' bounding boxes
  StepStats stats_;
  // The work and impulse of the external forces the modules apply (a confining pressure,
  // damping), by the trapezoidal rule over the steps, and their load in the last evaluated state.
  double externalWork_ = 0.0;
  std::array<double, 3> externalImpulse_{0.0, 0.0, 0.0};
  ExternalLoad external_;
};

} // namespace spall::methods
