#pragma once
// Personalised all-to-all of byte blocks (MPI_Alltoall of the sizes, then MPI_Alltoallv). The one
// communication primitive of migration and halo exchange. Physics-free.
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace spall::parallel {

struct ExchangeResult {
  std::vector<std::byte> data;         // received blocks, in source-rank order
  std::vector<std::size_t> countFrom;  // bytes received from each rank
  std::vector<std::size_t> offsetFrom; // where each rank's block starts in data
};

// `send` holds the blocks for ranks 0..size-1 back to back; `countTo[r]` bytes go to rank r.
ExchangeResult exchangeBytes(MPI_Comm comm, const std::vector<std::byte>& send,
                             const std::vector<std::size_t>& countTo);

// Element counts rather than bytes: returns how many elements each rank sends here.
std::vector<std::size_t> exchangeCounts(MPI_Comm comm, const std::vector<std::size_t>& countTo);

} // namespace spall::parallel
