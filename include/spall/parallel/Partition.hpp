#pragma once
// Who owns which part of the key space, and how to cut it. Physics-free.
//
// An ownership is a sorted list of key intervals [begin_k, begin_{k+1}) with an owner rank each.
// The space-filling-curve partitioner gives one contiguous interval per rank, cut where the
// cumulative cost reaches k/R of the total; METIS gives many intervals (SFC cells) per rank.
#include <mpi.h>

#include <cstdint>
#include <span>
#include <vector>

namespace spall::parallel {

class KeyOwnership {
public:
  KeyOwnership() = default;
  // One interval per rank: rank r owns [splitters[r], splitters[r+1]); splitters[0] = 0.
  static KeyOwnership contiguous(std::vector<std::uint64_t> splitters);
  // Arbitrary intervals; `begins` sorted ascending, begins[0] = 0.
  KeyOwnership(std::vector<std::uint64_t> begins, std::vector<int> ranks);

  int owner(std::uint64_t key) const;
  std::size_t intervals() const { return begins_.size(); }
  bool empty() const { return begins_.empty(); }
  const std::vector<std::uint64_t>& begins() const { return begins_; }
  const std::vector<int>& ranks() const { return ranks_; }

private:
  std::vector<std::uint64_t> begins_;
  std::vector<int> ranks_;
};

// The R - 1 cuts of the key axis that split the total integer cost into R nearly equal parts:
// splitter k is the smallest key s with cost(keys < s) >= ceil(k W / R). Found by bisection of the
// key axis with one allreduce per bit; integer costs make the result exact and independent of the
// rank count and of the order of summation. `keys` must be sorted, `cost` aligned with them.
std::vector<std::uint64_t> weightedSplitters(MPI_Comm comm, std::span<const std::uint64_t> keys,
                                             std::span<const std::uint64_t> cost);

// The same cuts for `ranks` ranks from every key at once (one process; `spall plan`'s virtual
// ranks): splitter k is the smallest s with cost(keys < s) >= ceil(k W / R), which is one past the
// key at which the running cost first reaches that target.
std::vector<std::uint64_t> splittersOf(std::span<const std::uint64_t> keys,
                                       std::span<const std::uint64_t> cost, int ranks);

// The graph of SFC cells handed to METIS_PartGraphKway: vertices are the occupied cells (key >>
// shift), weighted by cost; edges carry the number of interacting particle pairs between cells.
struct CellGraph {
  int shift = 0;                                           // cell = key >> shift
  std::vector<std::uint64_t> cells;                        // sorted cell ids
  std::vector<std::uint64_t> weight;                       // per cell
  std::vector<std::uint64_t> edgeFrom, edgeTo, edgeWeight; // undirected, as listed
};

struct MetisResult {
  KeyOwnership ownership;
  std::int64_t edgeCut = 0; // METIS objective: pairs cut, counted at cell granularity
  bool used = false;        // false: too few cells for the rank count (caller keeps SFC)
};

// Gathers the ranks' local cell graphs on rank 0, partitions there and broadcasts the result.
MetisResult metisPartition(MPI_Comm comm, const CellGraph& local);

} // namespace spall::parallel
