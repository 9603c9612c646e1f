#pragma once
// The material point method as one step list (MpmMethod::advance reads top to bottom): ghosts
// for the grid, the loads (the modules' hooks: damping, a confining pressure, fixed bodies), P2G,
// the grid's update, G2P, the ghosts' new velocities, the velocity gradient from the remapped
// grid (MUSL), density and energy, the material update, migration. The
// transfers are in solvers/MpmGrid, the materials the same `MaterialUpdate` SPH calls.
#include "spall/methods/ParticleMethod.hpp"
#include "spall/solvers/Config.hpp"
#include "spall/solvers/MpmGrid.hpp"

#include <memory>
#include <vector>

namespace spall::methods {

template <int Dim> class MpmMethod final : public ParticleMethod<Dim> {
public:
  MpmMethod(const parallel::MpiContext& mpi, MethodSetup setup, materials::MaterialUpdate materials,
            std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
            const ParticleFields<Dim>& f, Field<std::int32_t> cost,
            parallel::Decomposition<Dim>& decomposition);

  void start(const RunStart& run) override;
  void evaluate(std::int64_t step, double time) override;
  double advance(double dt, std::int64_t step, double time) override;
  // Probes and the penetration gauge sample within support() h: h is the particle's spacing
  // times nodes_per_h, as SPH's at the start.
  double support() const override { return 2.0; }
  solvers::GridNodes<Dim> gridNodes() override;
  void save(io::CheckpointState& st) const override;
  void restore(const io::CheckpointState& st) override;
  std::vector<MemoryPart> memoryParts() const override {
    return {{"halo", this->haloBytes()},
            {"mpm_grid", grid_ ? grid_->bytes() : 0},
            {"solver_scratch", allocatedBytes(fixedRow_, support_, order_, idRow_, idRowTmp_, L_,
                                              work_, rhoMid_, heat_, reach_, boxReach_) +
                                   this->loadBytes() + this->cellGridBytes()}};
  }

private:
  using Base = ParticleMethod<Dim>;
  using Base::checkFinite, Base::materialFields, Base::balance, Base::bookExternal,
      Base::externalLoad, Base::bookExternalStep;
  using Base::mpi_, Base::materials_, Base::modules_, Base::s_, Base::f_, Base::cost_,
      Base::decomposition_, Base::halo_, Base::stats_;

  std::pair<double, std::size_t> localTimeStep() const override;
  void exchangeHalo() override;
  double haloReachNeeded(bool* changed = nullptr) const; // collective
  void haloForStep();
  void makeGrid();
  void placeOrigin();
  solvers::MpmParticles<Dim> particles();
  void idOrder();
  void loads(double time);
  void deform(double dt);
  void migrateIfStale(double dt, std::int64_t step);

  MethodSetup setup_;
  Vec<Dim> origin_ = Vec<Dim>::Zero(); // the grid's node 0: set at t = 0, checkpointed
  bool originPlaced_ = false;
  double travel_ = 0.0;     // a bound on any point's travel since the last migration (checkpointed)
  bool rebalanced_ = false; // the last step ended in a rebalance
  // The ghosts kept across steps (haloForStep): the reach they were chosen with, a bound on any
  // point's travel since, and the store's layout then (a migration, an insertion or an erosion
  // changes it).
  double haloReach_ = 0.0, haloTravel_ = 0.0;
  std::uint64_t haloLayout_ = ~std::uint64_t{0};
  std::unique_ptr<solvers::MpmGrid<Dim>> grid_;
  std::vector<std::size_t> haloFields_, velocityField_;
  // Loads and supports: whether the step has any (damping, a pressure boundary, fixed bodies),
  // the columns the ghosts need for them, and each row's "fixed" flag.
  bool loaded_ = false;
  std::vector<std::size_t> loadFields_;
  std::vector<std::int32_t> fixedBodies_; // sorted
  std::vector<std::uint8_t> fixedRow_;    // per row (owned and ghosts): a fixed body's point
  std::vector<Vec<Dim>> support_;         // the step's support force on each owned point
  std::vector<std::uint32_t> order_;      // rows in id order: every node sums in it
  std::vector<Tensor<3>> L_;              // the step's velocity gradient (fluids: no L field)
  std::vector<double> work_, rhoMid_;     // deform(): sigma_n : D and rho_{n+1/2} per point
  std::vector<double> heat_; // friction (contact, walls): each owned point's J/kg a step
  bool rubs_ = false;        // contact = "friction" or a rigid wall with friction
  // Per material: whether it erodes with zero_stress (a failed point carries no stress).
  std::vector<std::uint8_t> zeroStress_;
  bool carriesNoStress(std::size_t i) const;
  // (id - min id, row) of every row, and the radix passes' other buffer (idOrder).
  std::vector<std::pair<ParticleId, std::uint32_t>> idRow_, idRowTmp_;
  std::vector<double> reach_;
  std::vector<Vec<Dim>> boxReach_;
};

} // namespace spall::methods
