#pragma once
// A deck's bodies made into a store of the unit tests' fields, with one ideal-gas material
// (the generator tests' fixture).
#include "spall/app/BodyGenerator.hpp"

#include "unit/FieldGroups.hpp"

#include <vector>

namespace spall::fixtures {

template <int Dim> struct GeneratedBodies {
  ParticleStore store;
  ParticleFields<Dim> f;
  std::vector<app::BodySummary> bodies;
  explicit GeneratedBodies(const Deck& deck) {
    registerFields(store, f);
    const std::vector<materials::Material> materials{{materials::IdealGas{1.4}, std::nullopt}};
    bodies = app::generateBodies<Dim>(deck, materials, store, f);
  }
};

} // namespace spall::fixtures
