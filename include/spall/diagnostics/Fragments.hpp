#pragma once
// Fragments: friends of friends across ranks (docs/reference.md, [fragments]). Two particles are
// friends when both are linkable (damage below the threshold) and closer than the mean of their
// link radii; a fragment is a connected set of friends, a particle with no friend a fragment of its
// own. Physics-free: rows are owned particles, then the ghosts of other ranks and periodic images
// (never wall images), the pairs those of a neighbor list of the owned rows.
//
// The search: a union-find over each rank's rows, then every component takes the smallest id it
// reaches, ghosts carrying their owner's label, until no label changes anywhere (as many rounds as
// a fragment crosses rank borders). The catalogue: each rank sums its share of every fragment and
// sends it to the rank that owns the label (a hash of it): one record per fragment and rank,
// however large the fragment. Masses, momenta and (along axes that are not periodic) first
// moments are summed exactly (FixedPoint), so a fragment's mass, velocity and centre, the order of
// fragments by mass (largest first, ties by label), and so each particle's place, are the same on
// any rank count; along a periodic axis the centre agrees to round-off. The totals
// meet on rank 0, which writes the catalogue. No rank ever holds all particles.
#include "spall/core/Types.hpp"
#include "spall/diagnostics/OrderFreeSums.hpp"
#include "spall/neighbors/NeighborList.hpp"

#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace spall::diagnostics {

template <int Dim> struct FragmentInput {
  std::span<const ParticleId> id;                 // rows
  std::span<const Vec<Dim>> x, v;                 // rows
  std::span<const double> m;                      // rows
  std::span<const double> linkRadius;             // rows: i and j link when r_ij <= (R_i + R_j) / 2
  std::span<const std::uint8_t> linkable;         // rows
  std::size_t owned = 0;                          // the first `owned` rows are this rank's
  const neighbors::NeighborList* pairs = nullptr; // of the owned rows; other indices are skipped
  std::array<double, Dim> period{};               // periodic box length per axis (0: not periodic)
};

struct Fragment {
  ParticleId label = 0; // the smallest id in it
  std::uint64_t particles = 0;
  double mass = 0.0;
  std::array<double, 3> x{}, v{}; // centre of mass and its velocity (unused axes 0)
};

struct FragmentCatalogue {
  std::vector<Fragment> fragments; // rank 0: all, largest mass first; other ranks: empty
  std::uint64_t count = 0;         // every rank
  std::vector<std::int64_t> index; // owned rows: the place of each particle's fragment
};

// Sends the owned rows' labels to the ghost rows (labels has a value for every row).
using GhostRefresh = std::function<void(std::vector<ParticleId>& labels)>;

template <int Dim>
FragmentCatalogue findFragments(const FragmentInput<Dim>& in, const GhostRefresh& refresh,
                                MPI_Comm comm);

} // namespace spall::diagnostics
