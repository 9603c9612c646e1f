#include "spall/app/FailureHint.hpp"

#include <fmt/format.h>

namespace spall::app {

std::string failureHint(const FailureSigns& s) {
  // Squeezed, or flung faster than any impact here (100 km/s).
  const bool wild = s.compression > 2.0 || s.speed > 1e5;
  if (s.mpm && s.frictionless && (wild || s.nonFinite))
    return "hint: with MPM and a velocity field per body (solver.contact = \"frictionless\" or "
           "\"friction\"), a point of one body amid "
           "another's material (debris) can be squeezed or flung: its field's nodes are held "
           "where they move toward the other body, not where they move away. One velocity "
           "field (\"welded\" or \"auto\") cannot do this; see decks/topics/mpm.md";
  if (!s.mpm && (s.compression > 10.0 || s.hRatio < 0.1))
    return "hint: compressed beyond any shock state (a shock compresses ~4-6x): particles "
           "are interpenetrating or pairing. Where bodies meet, solver.contact = "
           "\"frictionless\" and solver.stress_form = \"rho_product\" (the default) hold "
           "them apart; also a smaller solver.cfl or a finer resolution";
  if (!s.mpm && s.neighbors < 3 * s.dimension)
    return "hint: the particle has few neighbors: it has left its body (a fragment of one "
           "particle); solids under tension: solver.artificial_stress";
  // ASPH torn apart at km/s (the stability matrix's fine hydro cells at 6-10 km/s): a smaller
  // cfl fails more of them, and neither max_aspect_ratio, eos.min_pressure nor a relaxed shape
  // of H cures it (decks/topics/safe-defaults.md); SPH finishes them.
  if (s.asph && (s.nonFinite || s.energy) && s.pMin < 0.0)
    return fmt::format(
        "hint: an ASPH particle in tension (pressure down to {:.3g} Pa over its last steps): "
        "ASPH is not yet stable where a body is torn apart at km/s, and a smaller solver.cfl "
        "does not help there; solver.method = \"sph\" runs such scenes "
        "(decks/topics/safe-defaults.md)",
        s.pMin);
  if (s.nonFinite) return "hint: try a smaller solver.cfl; see decks/topics/failures.md";
  if (s.energy)
    return "hint: a run that creates energy is blowing up, most often where particles pair or "
           "interpenetrate; try a smaller solver.cfl or a finer resolution, and watch the "
           "particle above from the last good state. "
           "output.max_energy_error = 0 lets the run go on; see decks/topics/failures.md";
  return fmt::format("hint: a step below {:g} of run.end_time ({:.3e} s) counts as collapsed; see "
                     "decks/topics/failures.md",
                     s.collapseFraction, s.collapseFraction * s.endTime);
}

} // namespace spall::app
