#pragma once
// Bodies with `fixed = true` have no acceleration: the leapfrog keeps their velocity, zero (a
// clamp, which stays where it is) or the body's uniform `velocity` (a piston driven at it). They
// still carry density, stress and energy, and the forces they exert on the rest are the reaction of
// the support. The support's force on each particle, -m a of the rates it cancels, is an external
// force: its work (a piston's, F . v; a clamp's is zero) and impulse go in the books. MPM: the
// grid nodes they weigh on move at their velocity (solvers/MpmGrid); the impulse those nodes
// take from the step is shared among the fixed points there, and MpmMethod books it likewise.
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
    const auto m = s[f.m];
    support_.assign(s.localCount(), Vec<Dim>::Zero());
    for (std::size_t i = 0; i < s.localCount(); ++i)
      if (std::binary_search(bodies_.begin(), bodies_.end(), body[i])) {
        support_[i] = -m[i] * a[i];
        a[i].setZero();
      }
  }
  bool appliesExternalForces() const override { return true; }
  // The last evaluation's support forces: the rows are those of afterRates (nothing migrates
  // between a force evaluation and the booking of its state).
  void addExternalForces(const ParticleStore& s, const ParticleFields<Dim>& /*f*/, double /*time*/,
                         std::span<Vec<Dim>> F) const override {
    for (std::size_t i = 0; i < std::min(s.localCount(), support_.size()); ++i) F[i] += support_[i];
  }

private:
  std::vector<std::int32_t> bodies_;      // sorted body indices
  mutable std::vector<Vec<Dim>> support_; // per owned row, the last evaluation's
};

} // namespace spall::methods
