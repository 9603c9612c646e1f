#pragma once
// A particle method as the run loop sees it: one whole step, the stable time step, its
// counters and its restartable state. The run loop (app/) keeps time, output, checkpoints and
// signals, and knows nothing of how a method steps (SPH and ASPH now, MPM next).
#include "spall/core/Error.hpp"
#include "spall/core/MemoryAccounting.hpp"
#include "spall/diagnostics/Fragments.hpp"
#include "spall/io/Checkpoint.hpp"
#include "spall/methods/Module.hpp"
#include "spall/methods/StepStats.hpp"
#include "spall/solvers/GridNodes.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace spall::methods {

template <int Dim> class Method {
public:
  virtual ~Method() = default;
  // t = 0, the particles made (on any rank): the modules' initial fields, the material state
  // functions (p, cs).
  virtual void start(const RunStart& run) = 0;
  // The rates of the current state: before the first step of a new run (a restart reads the
  // checkpointed ones instead), or after a body joined. `step` is the step count so far, `time`
  // the state's time.
  virtual void evaluate(std::int64_t step, double time) = 0;
  // Advances the state from step `step` at time `time` by dt, then checks it (RunError naming
  // the particle and the field when a value went non-finite). Returns the step taken: dt, or
  // less where a particle's stable step fell below the finest one the step was begun with (time
  // bins: every particle then closes its step at the next substep).
  virtual double advance(double dt, std::int64_t step, double time) = 0;
  // The next stable time step over all ranks (collective); StepFailure naming the particle when
  // it collapsed below `floor`. advance() throws StepFailure for non-finite values.
  virtual double stableTimeStep(double floor, std::int64_t step, double time) = 0;
  // Collective diagnostics: the particle that sets the stable step now, and a particle by id
  // (a report with id 0 and no values when no rank holds it).
  virtual ParticleReport timeStepSetter() const = 0;
  virtual ParticleReport particle(ParticleId id) const = 0;
  // Friends of friends over the current particles (collective): fills the `fragment` field of
  // the owned particles and returns the catalogue (diagnostics/Fragments.hpp).
  virtual diagnostics::FragmentCatalogue findFragments(double linkLength,
                                                       double damageThreshold) = 0;
  // The work (J) and the impulse (N s) of the external forces on the particles since t = 0 (a
  // confining pressure, damping): what the total energy and momentum are expected to have gained.
  virtual double externalWork() const = 0;
  virtual std::array<double, 3> externalImpulse() const = 0;
  // MPM's background grid of the state now (collective), the nodes this rank writes in a
  // snapshot; a method without a grid has none.
  virtual solvers::GridNodes<Dim> gridNodes() { return {}; }
  // The kernel support in units of h (probes sample within it).
  virtual double support() const = 0;
  virtual StepStats& stats() = 0;
  // The method's restartable state beyond the particle fields (its modules' included).
  virtual void save(io::CheckpointState& st) const = 0;
  virtual void restore(const io::CheckpointState& st) = 0;
  // A module joining the running method, last in the list (a failed run's replay adds the
  // deformation gradient): its fields are registered now, and the caller sets their values.
  virtual void addModule(std::unique_ptr<Module<Dim>> module) = 0;
  // The bytes this rank's method holds allocated beyond the particle fields, by part
  // (summary.json's "memory_parts"): neighbor lists, the halo's plan, solver scratch, MPM's grid.
  virtual std::vector<MemoryPart> memoryParts() const = 0;
};

} // namespace spall::methods
