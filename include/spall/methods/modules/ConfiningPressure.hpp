#pragma once
// [[boundary]] type = "pressure": a confining pressure P(t) on a body's free surface (the
// confined rock targets of Austin 2013, Sec. 5.2 and Table 5.1).
//
// The force loop carries it (Sph::RatesLoop::surfaceSums and closeRow) as a shift of the stress in
// the momentum equation of the body's particles: row i sees sigma + P_i I for itself and for every
// neighbor, its own body's or another's. A uniform stress exerts no force, so the shift only acts
// where the support is cut, and there it is the traction -P n dA: on row i
//   a_i += P_i G_i,  G_i = sum_j m_j (u_i + u_j) s_i s_j grad_i W_ij  (u = 1/rho^2 or 1),
// the SPH operator's own surface: G_i vanishes in the interior and on a flat face its sum is the
// face's area over the mass (Sigma_i m_i G_i = -A n). What makes it robust:
// - a body at p = P everywhere is in equilibrium to round-off, however disordered its particles,
//   because the shift cancels exactly what the pressure itself exerts through the same operator
//   (corrected gradients, the rz weights and hoop force, ASPH included);
// - where another body, a wall's image or the rz axis's mirror fills the support, there is no
//   free surface and no load: a rod in contact feels the target's real stress, and the part of
//   the target it covers is not pushed twice. The other body feels no reaction (P is external).
// The energy equation keeps the real pressure: the load's work P dV enters as kinetic energy,
// and the method books it (externalPower) so that the conservation line stays meaningful.
// `surface_area` is each particle's share of the free surface, outward: -m_i G_i (m^2; a ring's
// area in rz, per unit thickness in 2D), so the load is -P surface_area.
// MPM makes the same shift on its grid, node by node (solvers/MpmGrid.hpp, MpmParticles::load).
#include "spall/methods/Module.hpp"

#include <utility>
#include <vector>

namespace spall::methods {

// A (time, value) table: linear between rows, the first value before the first row, the last
// after the last.
inline double tabulated(const std::vector<std::pair<double, double>>& table, double t) {
  if (table.empty()) return 0.0;
  if (t <= table.front().first) return table.front().second;
  for (std::size_t k = 1; k < table.size(); ++k)
    if (t < table[k].first) {
      const auto& [t0, v0] = table[k - 1];
      const auto& [t1, v1] = table[k];
      return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
    }
  return table.back().second;
}

template <int Dim> class ConfiningPressure final : public Module<Dim> {
public:
  struct Load {
    std::int32_t body;
    std::vector<std::pair<double, double>> pressure; // (s, Pa)
  };
  explicit ConfiningPressure(std::vector<Load> loads) : loads_(std::move(loads)) {}

  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    f.confiningPressure = s.add<double>("confining_pressure", kOutput | kCheckpoint);
    f.surfaceArea = s.add<Vec<Dim>>("surface_area", kOutput | kCheckpoint);
  }
  // P of each owned particle's body at the time of the force evaluation (0: not loaded). MPM
  // then leaves the load its nodes felt, whichever body's (solvers/MpmGrid.hpp).
  void beforeRates(ParticleStore& s, const ParticleFields<Dim>& f, double time) const override {
    const auto body = s[f.body];
    const auto P = s[f.confiningPressure];
    std::vector<double> byBody;
    for (const auto& l : loads_) {
      if (static_cast<std::size_t>(l.body) >= byBody.size())
        byBody.resize(static_cast<std::size_t>(l.body) + 1, 0.0);
      byBody[static_cast<std::size_t>(l.body)] = tabulated(l.pressure, time);
    }
    for (std::size_t i = 0; i < s.localCount(); ++i) {
      const auto b = static_cast<std::size_t>(body[i]);
      P[i] = b < byBody.size() ? byBody[b] : 0.0;
    }
  }
  // The load on the owned particles, -P_i A_i.
  bool appliesExternalForces() const override { return true; }
  void addExternalForces(const ParticleStore& s, const ParticleFields<Dim>& f, double /*time*/,
                         std::span<Vec<Dim>> F) const override {
    const auto P = s[f.confiningPressure];
    const auto A = s[f.surfaceArea];
    for (std::size_t i = 0; i < s.localCount(); ++i) F[i] -= P[i] * A[i];
  }

private:
  std::vector<Load> loads_;
};

} // namespace spall::methods
