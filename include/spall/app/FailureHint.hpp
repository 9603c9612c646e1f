#pragma once
// The hint a failed run's message ends with: what usually causes the failing particle's state,
// judged from that state and its last good steps (decks/topics/failures.md).
#include <string>

namespace spall::app {

struct FailureSigns {
  bool mpm = false;          // solver.method = "mpm" (no neighbors to count)
  bool asph = false;         // solver.method = "asph"
  bool frictionless = false; // solver.contact = "frictionless"
  bool nonFinite = false;    // a field went non-finite (else the step collapsed or...)
  bool energy = false;       // ... the run created energy (output.max_energy_error)
  int dimension = 3;
  double compression = 1.0; // density over its material's reference
  double hRatio = 1.0;      // h over its body's spacing
  double speed = 0.0;       // |v|, m/s
  int neighbors = 0;
  double pMin = 0.0;             // its lowest pressure over the good steps sampled (Pa); + if none
  double collapseFraction = 0.0; // a step below this fraction of the end time is a collapse
  double endTime = 0.0;          // run.end_time (s)
};

std::string failureHint(const FailureSigns& s);

} // namespace spall::app
