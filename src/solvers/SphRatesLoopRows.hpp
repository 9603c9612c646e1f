#pragma once
// SPH's force loop, what depends on j alone, of every row (ghosts included), once a loop: the
// options, the fields' spans, S_j / rho_j^2 (or S_j / rho_j for the product form), the
// reconstruction's strain rates, R_j, and the per-row factors of the pressure term. The pair
// loop (solvers/SphRatesLoop.hpp) then only adds and multiplies.
#include "SphRatesLoop.hpp"

namespace spall::solvers::sph {

template <int Dim, class K, bool Aniso>
template <Stress Mode>
void Sph<Dim, K, Aniso>::RatesLoop<Mode>::prepareRows() {
  Sph& o = o_;
  const ParticleFields<Dim>& f = o.f_;
  const SolverConfig& cfg = o.cfg_;
  balsara_ = cfg.artificial_viscosity.balsara;
  qc_ = 1.0 / cfg.nodes_per_h;
  product_ = cfg.stress_form == StressForm::RhoProduct;
  rz_ = cfg.geometry == Geometry::RZ;
  artificial_ = cfg.artificial_stress.enabled;
  reconstruct_ = Solid && cfg.artificial_viscosity.reconstruct;
  nAS_ = cfg.artificial_stress.exponent;
  // f_ij = W(r_ij)/W(dp) with dp = h/n_h, the initial spacing in units of h.
  invWdp_ = 1.0 / K::f(1.0 / cfg.nodes_per_h);
  alpha_ = cfg.artificial_viscosity.alpha, beta_ = cfg.artificial_viscosity.beta;
  sigma_ = K::sigma();
  frictionless_ = cfg.contact != Contact::Welded;
  body_ = frictionless_ ? o.s_[f.contactGroup] : o.s_[f.body];
  surfaces_ = f.surfaceArea.valid();
  if (surfaces_) P_ = o.s_[f.confiningPressure], area_ = o.s_[f.surfaceArea];
  acc_ = o.s_[f.a], dedt_ = o.s_[f.dedt], drhodt_ = o.s_[f.drhodt];
  sumWH_ = o.s_[f.sumWH], muMax_ = o.s_[f.muMax];
  if (balsara_) resizeWithHeadroom(o.divNew_, n_), resizeWithHeadroom(o.curlNew_, n_);
  if constexpr (Solid) {
    Sdev_ = o.s_[f.S], Lgrad_ = o.s_[f.L];
    prepareStressRows();
  }
  if constexpr (Corrected) Bcorr_ = o.s_[f.B];
  if constexpr (Aniso) o.prepareAnisoRows();
  prepareRowScratch();
  if (rz_) ring_ = o.ringR_.data();
  // Damaged pairs (solvers/CrackedPairs.hpp): a pair with a particle that failed (damage 1)
  // and can carry no tension, or with one between them, transmits compression only, as across
  // a contact (contactRule). Without it, the intact side's tension would still reach across the
  // failed layer through the pair's other half.
  damagedPairs_ = Solid && o.markCracks();
  if (damagedPairs_) o.cracks_.collect(nl_, n_);
}

// Solids: S/rho^2 (or S/rho), the reconstruction's strain rates and gates, R.
template <int Dim, class K, bool Aniso>
template <Stress Mode>
void Sph<Dim, K, Aniso>::RatesLoop<Mode>::prepareStressRows() {
  Sph& o = o_;
  const std::size_t all = o.s_.size();
  const bool product = product_, rz = rz_;
  const auto Sdev = Sdev_;
  const auto rho = rho_;
  resizeWithHeadroom(o.sOverRho_, all);
#pragma omp parallel for schedule(static) if (threaded(all))
  for (std::size_t j = 0; j < all; ++j)
    o.sOverRho_[j] = RowTensor::symmetricPart(Sdev[j]) / (product ? rho[j] : rho[j] * rho[j]);
  sOverRho_ = o.sOverRho_.data();
  // The strain rates of the reconstruction, of every row before this loop overwrites L (the
  // owned rows must read the previous loop's L, as ghosts do: else the sums depend on the
  // row order, and so on the rank count).
  if (reconstruct_) {
    resizeWithHeadroom(o.strainRate_, all);
    resizeWithHeadroom(o.isochoric_, all);
    const auto Lgrad = Lgrad_;
#pragma omp parallel for schedule(static) if (threaded(all))
    for (std::size_t j = 0; j < all; ++j) {
      const MatD Lj = Lgrad[j].template topLeftCorner<Dim, Dim>();
      o.strainRate_[j] = RowTensor::symmetricPart(Lj);
      // In rz the volume change includes the hoop rate D_tt = L(2,2): a mushroom's plastic
      // flow is isochoric in 3D, not in the r-z plane.
      o.isochoric_[j] = rz ? pair::isochoricGate<3>(0.5 * (Lgrad[j] + Lgrad[j].transpose()))
                           : pair::isochoricGate<Dim>(o.strainRate_[j].full());
    }
  }
  if (artificial_) {
    resizeWithHeadroom(o.artificialStress_, all);
    resizeWithHeadroom(o.tensile_, all);
    // Only solids: a fluid in a multi-material deck keeps the plain pressure term.
    const auto mat = o.s_[o.f_.material];
    const auto p = p_;
    const double epsilon = o.cfg_.artificial_stress.epsilon;
#pragma omp parallel for schedule(static) if (threaded(all))
    for (std::size_t j = 0; j < all; ++j) {
      o.artificialStress_[j] = o.solid_[static_cast<std::size_t>(mat[j])]
                                   ? RowTensor::symmetricPart(pair::artificialStress<Dim>(
                                         Sdev[j], p[j], rho[j], epsilon))
                                   : RowTensor::zero();
      o.tensile_[j] = o.artificialStress_[j].nonzero();
    }
    R_ = o.artificialStress_.data();
    tensile_ = o.tensile_.data();
  }
}

// The pair term's form and the Balsara switch enter as per-row factors, so that the pair loop
// has no branch on them: q = p/rho^2 and s = 1 (rho^2 form) or q = p and s = 1/rho (product
// form), the pressure term being (q_i + q_j) s_i s_j; f = the Balsara factor, or 1. (A
// multiplication by exactly 1 changes no bit: the rho^2 form without Balsara computes what it
// computed when each was an instantiation of its own.)
template <int Dim, class K, bool Aniso>
template <Stress Mode>
void Sph<Dim, K, Aniso>::RatesLoop<Mode>::prepareRowScratch() {
  Sph& o = o_;
  const std::size_t all = o.s_.size();
  const bool product = product_, balsara = balsara_;
  const auto h = h_, rho = rho_, p = p_, cs = cs_;
  const auto m = m_;
  const auto divv = balsara ? o.s_[o.f_.divv] : std::span<double>{};
  const auto curlv = balsara ? o.s_[o.f_.curlv] : std::span<double>{};
  const double sigma = sigma_;
  resizeWithHeadroom(o.rowScratch_, all);
#pragma omp parallel for schedule(static) if (threaded(all))
  for (std::size_t j = 0; j < all; ++j) {
    const double hjInv = 1.0 / h[j];
    o.rowScratch_[j] = {hjInv,
                        sigma * ipow<Dim>(hjInv) * hjInv,
                        m[j] / rho[j],
                        product ? p[j] : p[j] / (rho[j] * rho[j]),
                        product ? 1.0 / rho[j] : 1.0,
                        balsara ? pair::balsaraFactor(divv[j], curlv[j], cs[j], h[j]) : 1.0};
  }
  scratch_ = o.rowScratch_.data();
}

} // namespace spall::solvers::sph
