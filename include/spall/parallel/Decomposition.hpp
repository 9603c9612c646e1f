#pragma once
// Domain decomposition along a space-filling curve: which rank owns each particle, migration of
// every particle to its owner after each drift (however far it moved: the owner is found from
// the key, not from neighbouring domains), and rebalancing by measured cost. Physics-free: it
// moves whole rows of the particle store, so a field registered by any later module migrates
// without this code knowing it.
#include "spall/core/ParticleStore.hpp"
#include "spall/parallel/Partition.hpp"
#include "spall/parallel/SfcKeys.hpp"

#include <mpi.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace spall::neighbors {
struct NeighborList;
}

namespace spall::parallel {

struct DecompositionConfig {
  Curve curve = Curve::Hilbert;
  bool metis = false;
  int rebalanceEvery = 20;         // steps; 0: only on imbalance
  double imbalanceThreshold = 1.1; // max/mean cost that triggers a rebalance at any step
  int reorderEvery = 20;           // steps between sorts of the owned particles by key
};

struct MigrationStats {
  std::uint64_t moved = 0; // particles that changed rank (global)
  int maxRankDistance = 0; // largest |owner - old rank| (global): domains crossed in one step
};

struct RebalanceReport {
  double imbalanceBefore = 1.0, imbalanceAfter = 1.0; // max/mean cost over ranks
  std::int64_t metisEdgeCut = -1;                     // -1: SFC partition
  std::uint64_t moved = 0;
};

// What a checkpoint keeps of the decomposition: the key box and the key intervals of each rank.
struct DecompositionState {
  std::vector<double> box;           // lo[0..Dim), hi[0..Dim)
  std::vector<std::uint64_t> begins; // interval starts, ascending
  std::vector<std::int64_t> owners;  // rank of each interval
};

template <int Dim> class Decomposition {
public:
  Decomposition(MPI_Comm comm, DecompositionConfig config, Field<ParticleId> id, Field<Vec<Dim>> x,
                Field<std::int32_t> cost);

  // Start-up: every rank generated the same full particle set; keeps an even slice by index and
  // then partitions by key (unit cost) and migrates.
  void distributeInitial(ParticleStore& s);
  // Restart on another rank count (or curve): the particles are spread arbitrarily over the
  // ranks; partitions by key with their recorded cost and migrates.
  void distributeLoaded(ParticleStore& s);
  // Restart on the same rank count: every rank holds the rows it wrote; takes the key box and
  // the cuts back, so the run continues exactly as it would have.
  DecompositionState state() const;
  void restore(const DecompositionState& state);
  // After a drift: moves every owned particle whose key left this rank's part to its owner.
  MigrationStats migrate(ParticleStore& s, std::int64_t step);
  int reorderEvery() const { return cfg_.reorderEvery; }
  // max/mean of the summed cost over ranks (collective).
  double imbalance(const ParticleStore& s) const;
  bool rebalanceDue(std::int64_t step, double imbalance) const;
  // New key box, new cuts by cost, migration. `pairs` (rows of the owned particles, indices
  // into the store, ghosts included) feeds the METIS cell graph; it may be null for SFC.
  RebalanceReport rebalance(ParticleStore& s, const neighbors::NeighborList* pairs = nullptr);

private:
  void newKeyBox(const ParticleStore& s);
  MigrationStats moveToOwners(ParticleStore& s);
  void sortByKey(ParticleStore& s);

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  DecompositionConfig cfg_;
  Field<ParticleId> id_;
  Field<Vec<Dim>> x_;
  Field<std::int32_t> cost_;
  KeyMap<Dim> keys_;
  KeyOwnership owner_;
};

} // namespace spall::parallel
