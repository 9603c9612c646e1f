#pragma once
// What a method measures while it steps: wall time by phase and the decomposition's counters,
// for the closing summary, summary.json and tools/bench. One list of phases: the summary line,
// the JSON and the sum all read kPhaseNames.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace spall::methods {

enum Phase : int {
  kNeighbors,
  kDensity,
  kForces,
  kIntegration,
  kBoundaries,
  kExchange,
  kOutput,
  kCheckpoint,
  kPhaseCount
};
inline constexpr std::array<const char*, kPhaseCount> kPhaseNames = {
    "neighbors",  "density",  "forces", "integration",
    "boundaries", "exchange", "output", "checkpoint"};

struct Phases {
  std::array<double, kPhaseCount> seconds{};
  double operator[](Phase p) const { return seconds[p]; }
  double total() const {
    double t = 0.0;
    for (double s : seconds) t += s;
    return t;
  }
  template <class F> void time(Phase p, F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    seconds[p] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
};

struct StepStats {
  Phases phases;
  std::size_t pairs = 0;       // neighbor pairs summed over evaluations (owned rows)
  std::size_t evaluations = 0; // force evaluations
  std::size_t listBuilds = 0;  // neighbor searches (the rest filtered the wide list)
  std::size_t ghosts = 0;      // remote and periodic ghosts of the last evaluation
  std::uint64_t migrated = 0, migratedTotal = 0; // owned particles that changed rank
  std::uint64_t crossPairs = 0; // pairs whose partner is a remote or periodic ghost (sampled)
  int maxRankDistance = 0, rebalances = 0;
  double imbalance = 1.0, ghostFractionMax = 0.0;
  std::int64_t metisEdgeCut = -1;
  // The work against N x steps (solver.time_bins): substeps and rows whose rates were computed,
  // over the run and in the last step (this rank's); the bins' populations at the last step's
  // start (all ranks'; empty without bins).
  std::uint64_t substeps = 0, rowEvaluations = 0;
  std::uint64_t stepSubsteps = 0, stepRowEvaluations = 0;
  std::vector<std::uint64_t> binPopulation;
};

} // namespace spall::methods
