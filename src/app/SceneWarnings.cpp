#include "Simulation.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <limits>

// The scene's plausibility (docs/reference.md, "Warnings"): what needs the generated particles,
// beside the deck reader's checks of single values.
namespace spall::app {

template <int Dim> std::vector<DeckWarning> Simulation<Dim>::sceneWarnings() const {
  // Each body's extent along each axis and its fastest sound speed, over all ranks.
  const std::size_t nb = deck_.bodies.size();
  std::vector<double> lo(nb * Dim, std::numeric_limits<double>::infinity());
  std::vector<double> hi(nb * Dim, -std::numeric_limits<double>::infinity()), c(nb, 0.0);
  const auto x = store_[f_.x];
  const auto cs = store_[f_.cs];
  const auto v = store_[f_.v];
  const auto body = store_[f_.body];
  for (std::size_t i = 0; i < store_.localCount(); ++i) {
    const auto b = static_cast<std::size_t>(body[i]);
    for (int d = 0; d < Dim; ++d) {
      lo[b * Dim + d] = std::min(lo[b * Dim + d], x[i][d]);
      hi[b * Dim + d] = std::max(hi[b * Dim + d], x[i][d]);
    }
    c[b] = std::max(c[b], cs[i] + v[i].norm()); // a cold gas's signal is its flow (Noh)
  }
  MPI_Allreduce(MPI_IN_PLACE, lo.data(), static_cast<int>(lo.size()), MPI_DOUBLE, MPI_MIN,
                mpi_.comm());
  MPI_Allreduce(MPI_IN_PLACE, hi.data(), static_cast<int>(hi.size()), MPI_DOUBLE, MPI_MAX,
                mpi_.comm());
  MPI_Allreduce(MPI_IN_PLACE, c.data(), static_cast<int>(c.size()), MPI_DOUBLE, MPI_MAX,
                mpi_.comm());
  // The largest body present (rz: across its diameter) and its crossing time.
  const bool rz = deck_.run.geometry == Geometry::RZ;
  std::size_t largest = nb;
  double L = 0.0;
  for (std::size_t b = 0; b < nb; ++b) {
    if (!(hi[b * Dim] >= lo[b * Dim]) || !(c[b] > 0.0)) continue; // not in yet, or no sound
    double extent = 0.0;
    for (int d = 0; d < Dim; ++d)
      extent = std::max(extent, (rz && d == 0 ? 2.0 * hi[b * Dim] : hi[b * Dim + d]) -
                                    (rz && d == 0 ? 0.0 : lo[b * Dim + d]));
    if (extent > L) L = extent, largest = b;
  }
  if (largest == nb || !(L > 0.0)) return {};
  // A run of 1e-2 to 1e2 crossing times covers every scene here, from a wave's transit to a
  // damped settling; beyond it a time was typed in the wrong unit.
  constexpr double kMost = 100.0, kLeast = 0.01;
  const double tc = L / c[largest], ratio = deck_.run.end_time / tc;
  if (ratio <= kMost && ratio >= kLeast) return {};
  const std::string scene =
      fmt::format("the time a signal takes to cross body '{}' ({:.3g} m at {:.4g} m/s, sound "
                  "and flow: {:.3g} s)",
                  deck_.bodies[largest].name, L, c[largest], tc);
  return {{deck_.run.endTimeWhere,
           ratio > kMost ? fmt::format("'run.end_time' = {:.6g} s is {:.3g} times {}: ms or us "
                                       "typed for s?",
                                       deck_.run.end_time, ratio, scene)
                         : fmt::format("'run.end_time' = {:.6g} s is {:.3g} of {}: the run ends "
                                       "before the wave is 1% across; ns typed for us?",
                                       deck_.run.end_time, ratio, scene)}};
}

// MPM with a velocity field per body: the bodies under 2 cells across, by their shapes' smallest
// extent (rz: a box from the axis counts its radius), which contact may not stop.
template <int Dim> void Simulation<Dim>::warnThinBodies(double cell) {
  std::vector<std::string> thin;
  for (const auto& b : deck_.bodies) {
    const double width = thinnestWidth(b.shape);
    if (width < 2.0 * cell) thin.push_back(fmt::format("'{}' {:.3g} m", b.name, width));
  }
  if (thin.empty()) return;
  deferredWarnings_.push_back(fmt::format(
      "{}:{}: solver.contact = \"{}\" with MPM acts where the bodies' material fills "
      "90% of a node's support: bodies under 2 cells ({:.3g} m) across can pass through others "
      "unstopped ({}); a finer run.resolution or contact \"welded\" (decks/topics/mpm.md)",
      deck_.solver.where.file, deck_.solver.where.line, kContactNames(deck_.solver.contact),
      2.0 * cell, fmt::join(thin, ", ")));
}

template class Simulation<1>;
template class Simulation<2>;
template class Simulation<3>;

} // namespace spall::app
