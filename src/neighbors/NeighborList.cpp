// The neighbor search, instantiated here once for every dimension and support shape (declared
// extern in the header).
#include "spall/neighbors/NeighborList.hpp"

namespace spall::neighbors::detail {

SPALL_NEIGHBOR_SEARCHES()

} // namespace spall::neighbors::detail
