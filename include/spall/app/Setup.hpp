#pragma once
// Deck to objects: the materials, the physics modules in their fixed order, and the method's
// configuration. The one place that reads the deck's physics tables.
#include "spall/io/Deck.hpp"
#include "spall/materials/MaterialUpdate.hpp"
#include "spall/methods/MethodSetup.hpp"
#include "spall/methods/Module.hpp"
#include "spall/methods/MpmMethod.hpp"

#include <memory>
#include <string>
#include <vector>

namespace spall::app {

// EOS and strength of each material, in deck order.
std::vector<materials::Material> buildMaterials(const Deck& deck);

// The physics modules a deck needs, in the order they register fields and run their hooks.
// Throws DeckError for options that act on physics the deck does not have.
template <int Dim>
std::vector<std::unique_ptr<methods::Module<Dim>>> buildModules(const Deck& deck);

// The method's configuration: the rz axis first among the boundaries; for MPM the cell size
// resolved (twice the finest body spacing when not given, both after run.resolution).
methods::MethodSetup methodSetup(const Deck& deck);

// The method and its main settings, for the banner and `spall check`: "sph cubic_spline n_h 1.5 |
// density continuity", "mpm gimp cell 0.05 m flip 1".
std::string methodSummary(const Deck& deck);

} // namespace spall::app
