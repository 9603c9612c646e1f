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
  // The support's force on each row, from its last evaluation: a field, so that it moves with
  // the particle and a row the evaluation skipped (time bins) keeps it.
  void registerFields(ParticleStore& s, ParticleFields<Dim>& /*f*/) override {
    support_ = s.add<Vec<Dim>>("support_force", 0);
  }
  void afterRates(ParticleStore& s, const ParticleFields<Dim>& f, double /*time*/,
                  const EvaluatedRows& rows) const override {
    const auto body = s[f.body];
    const auto a = s[f.a];
    const auto m = s[f.m];
    const auto support = s[support_];
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::size_t i = rows[k];
      support[i].setZero();
      if (std::binary_search(bodies_.begin(), bodies_.end(), body[i])) {
        support[i] = -m[i] * a[i];
        a[i].setZero();
      }
    }
  }
  bool appliesExternalForces() const override { return true; }
  // Each row's support force from its last evaluation.
  void addExternalForces(const ParticleStore& s, const ParticleFields<Dim>& /*f*/, double /*time*/,
                         std::span<Vec<Dim>> F) const override {
    const auto support = s[support_];
    for (std::size_t i = 0; i < s.localCount(); ++i) F[i] += support[i];
  }

private:
  std::vector<std::int32_t> bodies_; // sorted body indices
  Field<Vec<Dim>> support_;
};

} // namespace spall::methods
