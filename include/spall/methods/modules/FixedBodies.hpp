#pragma once
// Bodies with `fixed = true` have no acceleration: the leapfrog keeps their velocity, zero (a
// clamp, which stays where it is) or the body's uniform `velocity` (a piston driven at it). They
// still carry density, stress and energy, and the forces they exert on the rest are the reaction of
// the support. MPM: the grid nodes they weigh on move at their velocity (solvers/MpmGrid).
#include "spall/methods/Module.hpp"

#include <algorithm>
#include <vector>

namespace spall::methods {

template <int Dim> class FixedBodies final : public Module<Dim> {
public:
  explicit FixedBodies(std::vector<std::int32_t> bodies) : bodies_(std::move(bodies)) {
    std::sort(bodies_.begin(), bodies_.end());
  }
  void registerFields(ParticleStore& /*s*/, ParticleFields<Dim>& /*f*/) override {}
  void afterRates(ParticleStore& s, const ParticleFields<Dim>& f, double /*time*/) const override {
    const auto body = s[f.body];
    const auto a = s[f.a];
    for (std::size_t i = 0; i < s.localCount(); ++i)
      if (std::binary_search(bodies_.begin(), bodies_.end(), body[i])) a[i].setZero();
  }

private:
  std::vector<std::int32_t> bodies_; // sorted body indices
};

} // namespace spall::methods
