#pragma once
// Turns the deck's bodies into particles: lattice points (cubic or hexagonal, optionally mapped
// by lattice_transform) clipped to each shape, with masses from the lattice volume, initial
// state from the material, stable ids in deck order and jitter drawn from (seed, id), never from
// the rank. Reports bodies with no particles and overlapping bodies as deck errors.
#include "spall/core/ParticleFields.hpp"
#include "spall/io/Deck.hpp"
#include "spall/materials/MaterialUpdate.hpp"

#include <string>
#include <vector>

namespace spall::app {

// " graded up to S m" for a graded body (its coarsest spacing after run.resolution), else "".
std::string gradedText(const Deck& deck, std::size_t body);

struct BodySummary {
  std::string name;
  std::size_t particles = 0;
  double mass = 0.0;
  double spacing = 0.0; // after run.resolution
};

// Fills the store's owned particles (all of them: the caller distributes) with the bodies present
// at t = 0; the summary counts every body, those that join later (insert_time > 0) too, and ids
// number every body in deck order.
template <int Dim>
std::vector<BodySummary> generateBodies(const Deck& deck,
                                        const std::vector<materials::Material>& materials,
                                        ParticleStore& store, const ParticleFields<Dim>& f);

// Appends body b's particles to the owned rows, ids from firstId (the t = 0 numbering), as
// generateBodies made them; every other field zero. Returns its summary, as generateBodies's.
template <int Dim>
BodySummary insertBody(const Deck& deck, const std::vector<materials::Material>& materials,
                       std::size_t b, ParticleId firstId, ParticleStore& store,
                       const ParticleFields<Dim>& f);

// Deposits each [[energy_source]] at t = 0, kernel-weighted over the particles within its radius
// (or into the nearest particle when the radius is zero).
template <int Dim>
void applyEnergySources(const Deck& deck, ParticleStore& store, const ParticleFields<Dim>& f);

// The transverse velocity at x of a body with cantilever_velocity (first bending mode).
double cantileverModeVelocity(const CantileverVelocityConfig& c, double x);

} // namespace spall::app
