#pragma once
// [damping]: dv/dt = a - c v on every particle while t < until (Austin 2013, Eq. 5.1), then
// off: a target is brought to its confining pressure and settles, and the shot follows in the
// same run. c dt is ~1e-3 in practice (c = 7.5e4/s, dt ~ 1e-8 s), far inside the explicit
// bound c dt < 2. The energy it takes out is booked as external work (externalPower).
// Fixed bodies keep their prescribed velocity: they are not damped. MPM takes the same a = -c v
// as a node force (methods/MpmMethod::loads).
#include "spall/methods/Module.hpp"

#include <algorithm>
#include <vector>

namespace spall::methods {

template <int Dim> class VelocityDamping final : public Module<Dim> {
public:
  VelocityDamping(double c, double until, std::vector<std::int32_t> fixedBodies)
      : c_(c), until_(until), fixed_(std::move(fixedBodies)) {
    std::sort(fixed_.begin(), fixed_.end());
  }
  void registerFields(ParticleStore& /*s*/, ParticleFields<Dim>& /*f*/) override {}
  void afterRates(ParticleStore& s, const ParticleFields<Dim>& f, double time,
                  const EvaluatedRows& rows) const override {
    if (!(time < until_)) return;
    const auto a = s[f.a];
    const auto v = s[f.v];
    const auto body = s[f.body];
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::size_t i = rows[k];
      if (!isFixed(body[i])) a[i] -= c_ * v[i];
    }
  }
  bool appliesExternalForces() const override { return true; }
  void addExternalForces(const ParticleStore& s, const ParticleFields<Dim>& f, double time,
                         std::span<Vec<Dim>> F) const override {
    if (!(time < until_)) return;
    const auto m = s[f.m];
    const auto v = s[f.v];
    const auto body = s[f.body];
    for (std::size_t i = 0; i < s.localCount(); ++i)
      if (!isFixed(body[i])) F[i] -= c_ * m[i] * v[i];
  }

private:
  bool isFixed(std::int32_t b) const { return std::binary_search(fixed_.begin(), fixed_.end(), b); }
  double c_, until_;
  std::vector<std::int32_t> fixed_; // sorted body indices
};

} // namespace spall::methods
