#pragma once
// The material point method's particle: a box of half-width l_p = (A_0)^(1/dim) / 2 around it,
// A_0 its volume m / rho at its start (in rz its area in the r-z plane, m / (2 pi r rho)): the
// body's spacing on a cubic lattice. Its GIMP weights average over the box; uGIMP keeps l_p as
// it was made (Bardenhagen & Kober 2004). CPDI's domain starts as that box, R = l_p I, and
// follows the motion (methods/MpmMethod: R_n+1 = (I + dt L) R_n); so does cpGIMP's, whose
// box is the domain's extent along the axes (solvers/MpmShapes.hpp, gimpBox). With APIC each point
// carries its velocity gradient C_p (solvers/MpmGrid.hpp).
#include "spall/methods/Module.hpp"
#include "spall/solvers/Config.hpp"

#include <cmath>
#include <numbers>

namespace spall::methods {

template <int Dim> class MaterialPoints final : public Module<Dim> {
public:
  MaterialPoints(bool axisymmetric, const MpmConfig& c)
      : rz_(axisymmetric), domains_(c.shape == MpmShape::Cpdi || c.shape == MpmShape::CpGimp),
        viscous_(c.viscous()), affine_(c.transfer == MpmTransfer::Apic) {}
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    f.halfWidth = s.add<double>("particle_half_width", kOutput | kCheckpoint | kHalo);
    if (domains_) f.domain = s.add<Tensor<Dim>>("particle_domain", kOutput | kCheckpoint | kHalo);
    if (viscous_)
      f.viscousPressure = s.add<double>("viscous_pressure", kOutput | kCheckpoint | kHalo);
    if (affine_) f.affine = s.add<Tensor<Dim>>("affine_velocity", kOutput | kCheckpoint | kHalo);
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    const auto m = s[f.m], rho = s[f.rho];
    const auto lp = s[f.halfWidth];
    const auto x = s[f.x];
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      const double ring = rz_ ? 2.0 * std::numbers::pi * x[i][0] : 1.0;
      lp[i] = 0.5 * std::pow(m[i] / (ring * rho[i]), 1.0 / Dim);
      if (domains_) s[f.domain][i] = lp[i] * Tensor<Dim>::Identity();
      if (viscous_) s[f.viscousPressure][i] = 0.0;
      if (affine_) s[f.affine][i].setZero();
    }
  }

private:
  bool rz_, domains_, viscous_, affine_;
};

} // namespace spall::methods
