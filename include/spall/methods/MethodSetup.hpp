#pragma once
// What a method (SphMethod, MpmMethod) is configured with (app/Setup fills it from the deck).
#include "spall/solvers/Config.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace spall::methods {

struct MethodSetup {
  SolverConfig solver; // MPM: its cell size resolved (app/Setup)
  // The deck's boundaries, in rz with the axis first (a folding mirror for SPH, a constrained
  // node plane for MPM).
  std::vector<BoundaryConfig> boundaries;
  std::vector<std::int32_t> fixedBodies; // bodies with `fixed = true` (MPM: their grid nodes)
  bool reproducible = true;              // neighbor sums in a rank-count-independent order
  double imbalanceThreshold = 1.1;       // a rebalance above it is worth a note
  bool timedCost = false;                // balance by measured time per counted pair
  std::function<void(const std::string&)> note; // a line for the run log (may be empty)
};

} // namespace spall::methods
