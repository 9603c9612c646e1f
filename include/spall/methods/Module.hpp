#pragma once
// A physics module: what a piece of physics adds to a method besides its pair terms. It
// registers its fields with the flags that route them (snapshots, checkpoints, halo, wall
// images), sets them at t = 0, acts at the hooks it needs, and saves its own state. The deck
// assembles the list once, in a fixed order (app/Setup.cpp); the method calls the hooks in list
// order. Hooks run once per step per module, never per particle.
#include "spall/core/ParticleFields.hpp"
#include "spall/io/Checkpoint.hpp"

#include <cstdint>
#include <span>

namespace spall::methods {

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
  // After each force evaluation, on the owned particles' rates.
  virtual void afterRates(ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/) const {}
  // Once per step, before the material update, with the step's dt: history that integrates the
  // velocity gradient the material update is about to use.
  virtual void beforeMaterials(ParticleStore& /*s*/, const ParticleFields<Dim>& /*f*/,
                               double /*dt*/) const {}
  // Restartable state beyond the module's fields (checkpoint state keys are the module's own).
  virtual void save(io::CheckpointState& /*st*/) const {}
  virtual void restore(const io::CheckpointState& /*st*/) {}
};

} // namespace spall::methods
