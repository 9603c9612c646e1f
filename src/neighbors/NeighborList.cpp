// The neighbor search, instantiated here once for every dimension and support shape.
#include "spall/neighbors/NeighborList.hpp"

namespace spall::neighbors::detail {

#define SPALL_NEIGHBOR_SEARCH(D, E)                                                                \
  template bool buildNeighborList<D, E>(std::span<const Vec<D>>, std::span<const double>,          \
                                        std::span<const Tensor<D>>, std::size_t, double,           \
                                        CellGrid<D>&, NeighborList&, const CanonicalOrder<D>*);
SPALL_NEIGHBOR_SEARCH(1, false)
SPALL_NEIGHBOR_SEARCH(2, false)
SPALL_NEIGHBOR_SEARCH(3, false)
SPALL_NEIGHBOR_SEARCH(1, true)
SPALL_NEIGHBOR_SEARCH(2, true)
SPALL_NEIGHBOR_SEARCH(3, true)
#undef SPALL_NEIGHBOR_SEARCH

} // namespace spall::neighbors::detail
