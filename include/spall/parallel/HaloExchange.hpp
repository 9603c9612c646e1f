#pragma once
// Remote ghosts: copies of other ranks' particles (and periodic images of anyone's, this rank's
// included) whose kernel support can reach a particle owned here. Physics-free: the caller says
// how far each particle reaches (support x h for SPH, the bounding box of the H ellipsoid for
// ASPH) and which fields to send.
//
// Which ranks need which particle: HaloBoxes.hpp (the rule, without MPI).
#include "spall/core/MemoryAccounting.hpp"
#include "spall/core/ParticleStore.hpp"
#include "spall/core/Types.hpp"
#include "spall/parallel/HaloBoxes.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace spall::parallel {

template <int Dim> class HaloExchange {
public:
  HaloExchange(MPI_Comm comm, std::vector<PeriodicAxis> periodic);

  // Drops all ghosts, finds which owned particles every rank needs and appends the ones this
  // rank needs as ghosts [localCount, localCount + ghosts()), with the listed fields (column
  // indices) filled; received positions get their periodic shift.
  void build(ParticleStore& s, Field<Vec<Dim>> x, std::span<const double> reach,
             std::span<const std::size_t> fields);
  // The same with ellipsoidal supports (ASPH): radius[i] encloses particle i's support and
  // halfWidth[i][d] is its half-width along axis d (its bounding box); a pair is complete when
  // either support's sphere and box both cover the other particle.
  void build(ParticleStore& s, Field<Vec<Dim>> x, std::span<const double> radius,
             std::span<const Vec<Dim>> halfWidth, std::span<const std::size_t> fields);
  // Re-sends the listed fields along the last build's plan (e.g. density after the summation;
  // positions get their periodic shift again).
  void refresh(ParticleStore& s, std::span<const std::size_t> fields);

  std::size_t ghosts() const { return received_; }
  // The plan's bytes (the rows to send and their shifts); the messages are made per exchange.
  std::size_t bytes() const {
    std::size_t b = allocatedBytes(rows_, codes_, shifts_, reachScratch_) + targets_.bytes();
    for (const auto& r : rows_) b += allocatedBytes(r);
    for (const auto& c : codes_) b += allocatedBytes(c);
    return b;
  }

private:
  void buildWith(ParticleStore& s, Field<Vec<Dim>> x, std::span<const double> radius,
                 std::span<const std::size_t> fields, bool round);
  void describeDomains(std::span<const Vec<Dim>> x, std::span<const Vec<Dim>> reach,
                       std::span<const double> radius, bool round);
  void plan(std::span<const Vec<Dim>> x, std::span<const Vec<Dim>> reach,
            std::span<const double> radius);

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  HaloTargets<Dim> targets_;                     // every rank's boxes (rebuilt with each build)
  std::vector<std::vector<std::uint32_t>> rows_; // owned rows to send, per rank
  std::vector<std::vector<std::uint8_t>> codes_; // periodic shift code of each, per rank
  std::size_t first_ = 0, received_ = 0;
  std::size_t position_ = 0;           // the position field's column
  std::vector<std::uint8_t> shifts_;   // each ghost's periodic shift code
  std::vector<Vec<Dim>> reachScratch_; // the owned particles' half-widths, per axis
};

} // namespace spall::parallel
