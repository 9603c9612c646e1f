#pragma once
// `spall element`: one material point driven through a deformation-gradient history (an F-table,
// io/FTable.hpp) by the same material update a run uses (docs/reference.md, "Single-element
// driver").
#include <optional>
#include <string>
#include <vector>

namespace spall::app {

struct ElementOptions {
  std::string deckPath;
  std::vector<std::string> overrides; // --set KEY=VALUE, as for `spall run`
  std::string material;               // the deck material to drive
  std::string table;                  // the F-table
  std::string output;                 // the CSV written
  int substeps = 100;                 // steps between two rows of the table
  // How a step's velocity gradient comes from F_n and F_n+1 (--kinematics). "run" (Austin 2013,
  // Eq. 4.10): L = (F_n+1 F_n^-1 - I)/dt, the inverse of a run's update F_n+1 = (I + dt L) F_n, so
  // a particle's recorded history replays exactly. "midpoint" (his Eq. 4.8): L = (F_n+1 - F_n)/dt
  // ((F_n+1 + F_n)/2)^-1, whose symmetric part vanishes for any rotation increment (a Cayley
  // transform): with the strength models' Hughes-Winget update a superimposed rotation is then
  // followed exactly. "run" reads a rotation increment dtheta as a strain of -dtheta^2/2.
  // Unset (no --kinematics): midpoint for a table, whose rotation must not show as a pressure;
  // run for a recorded particle (--state), which must see what the run handed it (kinematicsFor).
  enum class Kinematics { Run, Midpoint };
  std::optional<Kinematics> kinematics;
  // A recorded particle's state (particles/particle_ID.csv of a run): at each table row the
  // material update gets the density and energy the run's update saw, then the state is
  // re-evaluated at the row's (kick-corrected) density and energy, as a run's step does; so the
  // material sees what the particle had (one substep a row; the rows' times must be the table's).
  std::string state;
  bool everySubstep = false; // a CSV row per substep, not per table row
  bool overwrite = false;
  double flawVolume = 1.0e-9; // m^3: the volume a Grady-Kipp material's flaws are drawn for
};

// The kinematics a drive uses: the one asked for, else midpoint for a table and run with --state.
ElementOptions::Kinematics kinematicsFor(const ElementOptions& options);

// Throws DeckError (deck or table, exit 2), UsageError (options, exit 2) or RunError (the
// material failed: non-finite state, exit 1). The CSV appears only once complete, or once the
// material failed (with the rows before the failure: a failed run's particle, replayed).
void runElement(const ElementOptions& options);

} // namespace spall::app
