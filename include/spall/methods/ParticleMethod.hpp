#pragma once
// What every particle method shares beyond its step: the modules and the material update, the
// store and the decomposition, the halo, the external forces' books, the reports that name a
// particle (a collapsed time step, a non-finite state), friends of friends, rebalancing and the
// restartable counters. A method (SphMethod, MpmMethod) adds its step, its ghosts and its
// stable time step.
#include "spall/core/Error.hpp"
#include "spall/core/ParticleFields.hpp"
#include "spall/materials/MaterialUpdate.hpp"
#include "spall/methods/Method.hpp"
#include "spall/methods/MethodSetup.hpp"
#include "spall/methods/Module.hpp"
#include "spall/neighbors/NeighborList.hpp"
#include "spall/parallel/Decomposition.hpp"
#include "spall/parallel/HaloExchange.hpp"
#include "spall/parallel/Mpi.hpp"

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace spall::methods {

// What the shared part is configured with.
struct ParticleMethodSetup {
  std::vector<parallel::PeriodicAxis> periodic;
  double imbalanceThreshold = 1.1;              // a rebalance above it is worth a note
  bool timedCost = false;                       // balance by measured time per counted pair
  double nodesPerH = 1.5;                       // h per particle spacing (fragments' link length)
  std::function<void(const std::string&)> note; // a line for the run log (may be empty)
};
// The shared part of a method's setup: periodic axes from the boundaries, h per spacing.
ParticleMethodSetup sharedSetup(const MethodSetup& s);

template <int Dim> class ParticleMethod : public Method<Dim> {
public:
  // The store's fields are registered (by `modules`) before the method is made.
  ParticleMethod(const parallel::MpiContext& mpi, ParticleMethodSetup setup,
                 materials::MaterialUpdate materials,
                 std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
                 const ParticleFields<Dim>& f, Field<std::int32_t> cost,
                 parallel::Decomposition<Dim>& decomposition);

  diagnostics::FragmentCatalogue findFragments(double linkLength, double damageThreshold) override;
  double stableTimeStep(double floor, std::int64_t step, double time) override;
  ParticleReport timeStepSetter() const override;
  ParticleReport particle(ParticleId id) const override;
  double externalWork() const override { return externalWork_; }
  std::array<double, 3> externalImpulse() const override { return externalImpulse_; }
  StepStats& stats() override { return stats_; }
  void save(io::CheckpointState& st) const override;
  void restore(const io::CheckpointState& st) override;
  void addModule(std::unique_ptr<Module<Dim>> module) override {
    module->registerFields(s_, f_);
    modules_.push_back(std::move(module));
  }

protected:
  // This rank's stable time step and the owned row that sets it.
  virtual std::pair<double, std::size_t> localTimeStep() const = 0;
  // Remote (and periodic) ghosts of every field a pair loop reads, within each owned particle's
  // support: what friends of friends links across rank borders.
  virtual void exchangeHalo() = 0;

  // The parts every particle method has: the halo's plan, the cell grid, the loads' scratch.
  std::size_t haloBytes() const { return halo_.bytes(); }
  std::size_t cellGridBytes() const { return grid_.bytes(); }
  std::size_t loadBytes() const { return allocatedBytes(externalForce_); }

  // all ranks; `extra`: forces on the owned rows beside the modules' (MPM's supports)
  ExternalLoad externalLoad(double time, std::span<const Vec<Dim>> extra = {}) const;
  void bookExternal(double dt, const ExternalLoad& now);
  // A method whose loads act through the whole step from one state (MPM): dt times their load.
  void bookExternalStep(double dt, const ExternalLoad& load);
  materials::MaterialFields materialFields();
  void checkFinite(std::int64_t step, double time) const;
  // Measures the imbalance of the cost and re-cuts the key axis when due; the pairs (the owned
  // rows', if any) are the graph METIS cuts.
  void balance(std::int64_t step, const neighbors::NeighborList* pairs);
  // decomposition.cost = "timed": each owned particle's counted cost times its rank's measured
  // seconds per counted unit since the last cut, over the mean of all ranks'.
  void weighByTime();

  const parallel::MpiContext& mpi_;
  ParticleMethodSetup common_;
  materials::MaterialUpdate materials_;
  std::vector<std::unique_ptr<Module<Dim>>> modules_;
  ParticleStore& s_;
  ParticleFields<Dim> f_;
  Field<std::int32_t> cost_;
  parallel::Decomposition<Dim>& decomposition_;
  parallel::HaloExchange<Dim> halo_;
  neighbors::CellGrid<Dim> grid_;
  StepStats stats_;
  double countedWork_ = 0.0;  // this rank's counted cost summed over the steps since the cut
  double secondsAtCut_ = 0.0; // its compute phases' seconds at the last cut
  // The work and impulse of the external forces the modules apply (a confining pressure,
  // damping), by the trapezoidal rule over the steps, and their load in the last evaluated state.
  double externalWork_ = 0.0;
  std::array<double, 3> externalImpulse_{0.0, 0.0, 0.0};
  ExternalLoad external_;
  mutable std::vector<Vec<Dim>> externalForce_; // scratch of externalLoad: each owned row's

private:
  // The fields of owned row i that no state can have (non-finite, non-positive density or h):
  // visit(name) for each; badFields joins their names.
  template <class Visit> void forEachBadField(std::size_t i, Visit&& visit) const;
  std::string badFields(std::size_t i) const;
  ParticleId setterId(double dtLocal, double dt, std::size_t which) const;
  bool gather(ParticleReport& fault, ParticleId mine, std::size_t row, std::string& fields) const;
  [[noreturn]] void raise(ParticleReport fault, ParticleId mine, std::size_t row) const;
};

} // namespace spall::methods
