#pragma once
// A physics module: what a piece of physics adds to a method besides its pair terms. It
// registers its fields with the flags that route them (snapshots, checkpoints, halo, wall
// images), sets them at t = 0, acts at the hooks it needs, and saves its own state. The deck
// assembles the list once, in a fixed order (app/Setup.cpp); the method calls the hooks in list
// order. Hooks run once per step per module, never per particle.
#include "spall/core/EvaluatedRows.hpp"
#include "spall/core/ParticleFields.hpp"
#include "spall/io/Checkpoint.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace spall::methods {

// What the external forces a module applies do to the owned particles in a state: their power
// (W) and their sum (N), for the conservation line's books.
struct ExternalLoad {
  double power = 0.0;
  std::array<double, 3> force{0.0, 0.0, 0.0};
};

// What a new run knows at t = 0 beyond the particles a rank owns, or, when a body joins the run
// later (insert_time), which owned rows are new.
struct RunStart {
  std::span<const std::uint64_t> bodyParticles; // every body's particle count, on all ranks
  std::size_t first = 0;                        // the first owned row to initialise
};

template <int Dim> class Module {
public:
  virtual ~Module() = default;
  // Registers the module's fields in the store and records their handles in f.
  virtual void registerFields(ParticleStore& s, ParticleFields<Dim>& f) = 0;
  // A new run at t = 0, after the bodies are made, or a body joining it: initial values of the
  // owned particles from row start.first on.
  virtual void initialise(ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/,
                          const RunStart& /*start*/) const {}
  // Before each force evaluation of the state at `time`: what the force loop reads of the owned
  // particles besides their state (a boundary load now).
  virtual void beforeRates(ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/,
                           double /*time*/) const {}
  // After each force evaluation of the state at `time`, on the rates of the rows it computed.
  virtual void afterRates(ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/, double /*time*/,
                          const EvaluatedRows& /*rows*/) const {}
  // Whether the module applies external forces (then the method books their work).
  virtual bool appliesExternalForces() const { return false; }
  // The external force (N) the module applies to each owned particle in the state at `time`
  // (the last evaluation's), added to F (one per owned row): the method books their power and
  // sum for the conservation line, summed in an order-free way (diagnostics/Conservation.hpp).
  virtual void addExternalForces(const ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/,
                                 double /*time*/, std::span<Vec<Dim>> /*F*/) const {}
  // Once per step, before the material update, with the step's dt: history that integrates the
  // velocity gradient the material update is about to use.
  virtual void beforeMaterials(ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/,
                               double /*dt*/) const {}
  // Restartable state beyond the module's fields (checkpoint state keys are the module's own).
  virtual void save(io::CheckpointState& /*st*/) const {}
  virtual void restore(const io::CheckpointState& /*st*/) {}
};

} // namespace spall::methods
