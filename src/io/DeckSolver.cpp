// What the material point method does not take yet ([solver] itself is read in
// keys/SolverKeys.cpp).
#include "DeckDetail.hpp"

namespace spall::io::deck_detail {

// What the material point method does not take yet: an error where the deck asks for it (the
// method's line where the deck has no place of its own for it).
void checkMpmScope(const Deck& deck) {
  if (deck.solver.method != SolverMethod::Mpm) return;
  const auto fail = [](const SourceLocation& where, const std::string& what) {
    throw DeckError(where, what + " is not available with solver.method = \"mpm\" yet");
  };
  if (deck.decomposition.partitioner == Partitioner::Metis)
    fail(deck.solver.where, "decomposition.partitioner = \"metis\" (a graph of neighbor pairs)");
  for (const auto& b : deck.boundaries)
    if (b.type == BoundaryType::Periodic) fail(b.where, "a boundary of type 'periodic'");
  // The grid's cell is one size; particles of many sizes would see it differently.
  for (const auto& b : deck.bodies)
    if (b.grading) fail(b.grading->where, "a graded body (body '" + b.name + "', grading)");
  // The grid is solved for every node at once: one step for all its points.
  if (deck.solver.time_bins > 1)
    fail(deck.solver.where, "solver.time_bins = " + std::to_string(deck.solver.time_bins) +
                                " (each point its own step)");
}

} // namespace spall::io::deck_detail
