#pragma once
// The decomposition of a particle set over R virtual ranks on one process: what a run on R ranks
// makes at its start (Decomposition::distributeInitial, then HaloExchange::build), without MPI
// and without physics. Each rank owns a contiguous range of the space-filling curve cut at equal
// particle counts (unit costs, as a new run starts), its owned particles in (key, id) order; its
// ghosts are those HaloBoxes.hpp's rule sends it. The counts are those of the run, exactly.
// Physics-free: the caller says where the particles are and how far each reaches.
#include "spall/core/Types.hpp"
#include "spall/parallel/HaloBoxes.hpp"
#include "spall/parallel/SfcKeys.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace spall::parallel {

template <int Dim> struct VirtualParticles {
  std::span<const Vec<Dim>> x;
  std::span<const ParticleId> id;
  std::span<const Vec<Dim>> reach; // half-width of each particle's support along each axis
  std::span<const double> radius;  // radius of a sphere enclosing it
  bool round = true;               // supports are spheres (reach = radius on every axis)
  std::vector<PeriodicAxis> periodic;
  Curve curve = Curve::Hilbert;
};

struct VirtualRank {
  std::uint64_t owned = 0;
  std::uint64_t ghosts = 0;  // received: remote ghosts and its own periodic images
  std::uint64_t sent = 0;    // rows it sends to other ranks (periodic self-images excluded)
  std::uint32_t sendsTo = 0; // ranks it sends rows to
  std::uint32_t receivesFrom = 0;
  std::uint32_t neighbors = 0; // ranks it exchanges with either way
};

// Sorted once, cut for any rank count.
template <int Dim> class VirtualRanks {
public:
  explicit VirtualRanks(VirtualParticles<Dim> particles);
  std::size_t size() const { return order_.size(); }
  std::vector<VirtualRank> cut(int ranks) const;

private:
  VirtualParticles<Dim> p_;
  std::vector<std::uint64_t> keys_;  // in (key, id) order
  std::vector<std::uint32_t> order_; // row of each, in (key, id) order
};

} // namespace spall::parallel
