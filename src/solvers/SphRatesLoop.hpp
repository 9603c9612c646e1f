#pragma once
// SPH's and ASPH's force loop: the rates of every owned particle from its neighbors (the
// declaration's comment in Sph.hpp says what it computes and why). It reads as the list of the
// terms it adds (RatesLoop::visitPair): a row opens with its own values, each pair adds its
// named terms, and the row closes with the rz hoop closure and its writes. The terms' physics is
// in solvers/SphPairTerms.hpp and solvers/Axisymmetric.hpp; each term here is what a row sums.
// (Every term is inlined into the one pair loop: the loop is register-bound, so the terms must
// not become calls. Each keeps its arithmetic in the order it always had, so the sums are the
// same bits.)
#include <limits>

#include "Sph.hpp"

namespace spall::solvers::sph {

template <int Dim, class K, bool Aniso> template <Stress Mode> class Sph<Dim, K, Aniso>::RatesLoop {
  static constexpr bool Solid = Mode != Stress::Pressure;
  static constexpr bool Corrected = Mode == Stress::CorrectedCauchy;
  using MatD = Tensor<Dim>;
  using RowKernels = std::conditional_t<Aniso, AnisoPairKernels, PairKernels>;

public:
  RatesLoop(Sph& sph, const neighbors::NeighborList& nl, std::size_t firstWallImage)
      : o_(sph), nl_(nl), firstWallImage_(firstWallImage), x_(sph.s_[sph.f_.x]),
        v_(sph.s_[sph.f_.v]), h_(sph.s_[sph.f_.h]), m_(sph.planarMass()), rho_(sph.s_[sph.f_.rho]),
        p_(sph.s_[sph.f_.p]), cs_(sph.s_[sph.f_.cs]), mass_(sph.s_[sph.f_.m]),
        n_(sph.s_.localCount()) {
    prepareRows();
  }

  void run() {
    // Rows in parallel (core/Threads.hpp): each writes only its own rates, from its neighbors'
    // inputs in its list's order; chunks of rows handed out as threads free up (rows differ in
    // neighbor count and in how many pairs approach).
    const EvaluatedRows rows = o_.passRows(n_);
#pragma omp parallel for schedule(dynamic, 64) if (threaded(rows.size()))
    for (std::size_t slot = 0; slot < rows.size(); ++slot) {
      const std::size_t i = rows[slot];
      thread_local std::vector<std::uint32_t> rowBuf; // each thread's own
      thread_local RowKernels kernels;                // each thread's own
      const auto row = nl_.of(i, rowBuf);
      Row r;
      openRow(r, i);
      // The reconstruction's own values apart from the row: a call takes their address, and a
      // struct with a member a call sees stays in memory whole (in the row, its sums left the
      // registers: the loop 10-15% slower).
      ReconstructionRow recon;
      if constexpr (Solid)
        if (reconstruct_) recon = o_.reconstructionRow(i);
      kernelPass(r, row, kernels);
      for (std::size_t k = 0; k < row.size(); ++k) visitPair(r, recon, kernels, k, row[k]);
      closeRow(r);
    }
    if (balsara_) {
      const auto divv = o_.s_[o_.f_.divv], curlv = o_.s_[o_.f_.curlv];
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const std::size_t i = rows[k];
        divv[i] = o_.divNew_[i], curlv[i] = o_.curlNew_[i];
      }
    }
  }

private:
  // What the row's particle i brings (read once) and what its pairs sum.
  struct Row {
    std::size_t i;
    Vec<Dim> xi, vi;
    double hi, rhoi, ci;
    double qI, sI, fi; // the pressure term's factors and the Balsara factor (RowScratch)
    double uI;         // q of a unit pressure (the confining pressure's surface sums)
    std::int32_t bodyi;
    bool tensileI; // R_i != 0: i is in tension (artificial stress)
    // Solids: S_i / rho_i^2 (or S_i / rho_i for the product form) in the Dim x Dim block, R_i,
    // B_i. The row's own tensors as full ones: kept as SymTensor here, taylor_bar_3d's step took
    // 25% longer.
    MatD SiOwn, Ri, Bi;
    // The sums: acceleration, the confining pressure's G_i, de/dt, -div v, Psi_0's sum, the
    // largest mu_ij, Balsara's div v and curl v, the velocity gradient L_i.
    Vec<Dim> ai, Gi;
    double dei, drhoi, sumWHi, mui, divi;
    // The pairs across a contact, apart (contactStrain): their share of -div v and of L, and
    // the nearest one's distance over the pair's mean spacing, squared.
    double drhoAcross, nearAcross2;
    MatD LAcross;
    Eigen::Matrix<double, Dim == 3 ? 3 : 1, 1> curli;
    MatD Li;
    // rz: -sum_j V_j x_ij,r g_ij,r with the velocity gradient's and the divergence's kernel
    // gradients, the normalisation the hoop rate is given (solvers/Axisymmetric.hpp); k_r, its
    // share from pairs across a contact or crack (where i's own stress enters as -max(p_i, 0) I
    // only), and the artificial stress's share; the hoop strain rate D_tt.
    double Mrr, MrrVolume, kr, krAcross, krAS, Dtt;
  };
  // One pair (i, j) of the row.
  struct Pair {
    std::uint32_t j;
    Vec<Dim> xij, vij;
    double r2;
    // The pair's gradient (the mean of both supports'), i's own one (continuity), and the
    // gradients i's and j's own quantities are contracted with (the same unless corrected).
    Vec<Dim> gradW, gradWi, gI, gJ;
    double vgrad;     // v_ij . grad W
    double hbarOverR; // ASPH: the mean smoothing scale along the pair over r (its viscosity)
    double qMean;     // the pair's mean normalised distance
    double Pij;       // the viscosity Pi_ij
    bool cracked;     // a damaged pair (solvers/CrackedPairs.hpp)
    bool across;      // across a contact or a crack: compression only
    double qOwn, qOther, sij; // the pressure term's factors of the pair
    double mj, wVol, w;       // m_j and V_j, weighted by Rbar/R_i in rz; w that weight
  };

  // ---- the pair: its terms in the order they are added ------------------------------------
  [[gnu::always_inline]] void visitPair(Row& r, const ReconstructionRow& recon,
                                        const RowKernels& kernels, std::size_t k,
                                        std::uint32_t j) const {
    Pair p;
    if (!geometry(r, kernels, k, j, p)) return;
    viscosity(r, recon, p);
    contactRule(r, p);
    axisymmetricWeight(r, p);
    pressureForce(r, p);
    surfaceSums(r, p);
    if constexpr (Solid)
      if (!p.across) {
        deviatoricStress(r, p);
        artificialStress(r, p);
      }
    energyShare(r, p);
    continuity(r, p);
    balsaraSums(r, p);
  }

  // The pair's kernel gradients from the row's kernel pass. False for a pair that exerts
  // nothing: coincident particles (in x, or in eta through underflow).
  [[gnu::always_inline]] bool geometry(Row& r, const RowKernels& kernels, std::size_t k,
                                       std::uint32_t j, Pair& p) const {
    p.j = j;
    p.xij = r.xi - x_[j];
    p.r2 = p.xij.squaredNorm();
    if (p.r2 == 0.0) return false;
    if constexpr (Aniso) {
      if (kernels.coincident[k] != 0.0) return false;
      for (int d = 0; d < Dim; ++d) p.gradWi[d] = kernels.gWi(d, k), p.gradW[d] = kernels.gW(d, k);
      p.hbarOverR = kernels.hbarOverR[k];
    } else {
      p.gradW = kernels.gW[k] * p.xij;
      p.gradWi = kernels.gWi[k] * p.xij;
    }
    p.qMean = kernels.qMean[k];
    r.sumWHi += kernels.wH[k];
    p.gI = p.gradW;
    p.gJ = p.gradW;
    if constexpr (Corrected) {
      p.gI = r.Bi * p.gradW;
      p.gJ = Bcorr_[j].template topLeftCorner<Dim, Dim>() * p.gradW;
    }
    p.vij = r.vi - v_[j];
    p.vgrad = p.vij.dot(p.gradW);
    return true;
  }

  // Monaghan & Gingold (1983) viscosity (Lam et al. 2001, Eqs. 22-24) of an approaching pair,
  // from the approach reconstructed to the pair's midpoint where asked (Frontiere, Raskin &
  // Owen 2017) and scaled by the pair's mean Balsara factor (exactly 1 without the switch),
  // which a pair closer than the mean spacing takes back as the reconstruction does
  // (pair::balsaraPair). A rigid wall's image exerts none (Boundaries::holdAcceleration holds
  // the wall).
  [[gnu::always_inline]] void viscosity(Row& r, const ReconstructionRow& recon, Pair& p) const {
    const std::uint32_t j = p.j;
    double vr = j < firstWallImage_ ? p.vij.dot(p.xij) : 0.0;
    p.Pij = 0.0;
    if constexpr (Solid)
      if (reconstruct_ && vr < 0.0) {
        const Vec<Dim> xij = p.xij; // (a copy: the call takes its address, not the pair's)
        vr = o_.reconstructedApproach(vr, xij, recon, j, p.qMean);
      }
    if (vr < 0.0) {
      const double hbar = Aniso ? p.hbarOverR * std::sqrt(p.r2) : 0.5 * (r.hi + h_[j]);
      double mu;
      p.Pij = pair::viscosity(vr, p.r2, hbar, 0.5 * (r.ci + cs_[j]), 0.5 * (r.rhoi + rho_[j]),
                              alpha_, beta_, mu);
      if (balsara_) p.Pij *= pair::balsaraPair(r.fi, scratch_[j].balsara, p.qMean, qc_);
      r.mui = std::max(r.mui, -mu);
    }
  }

  // Frictionless contact between bodies (contact groups) and damaged pairs: across a group
  // boundary or a crack only compression is transmitted (no tension, no shear), so bodies can
  // slide and separate and an open crack pulls on nothing. Each side's pressure term then takes
  // its normal compression along the pair, max(-n . sigma . n, 0); the deviatoric and artificial
  // stress are left out (visitPair).
  [[gnu::always_inline]] void contactRule(const Row& r, Pair& p) const {
    const std::uint32_t j = p.j;
    p.cracked = false; // (only solids crack: a constant the hydro loop folds away)
    if constexpr (Solid)
      p.cracked = damagedPairs_ && o_.cracks_.cracked(r.i, j, std::span<const Vec<Dim>>(x_),
                                                      [this](std::size_t a, std::size_t b) {
                                                        return interacts(a, b);
                                                      });
    p.across = (frictionless_ && body_[j] != r.bodyi) || p.cracked;
    p.qOwn = r.qI, p.qOther = scratch_[j].q;
    if (p.across) {
      const double rhoj = rho_[j];
      // What crosses is the normal compression along the pair, -n . sigma . n = p - n . S . n
      // (n = x_ij/r_ij), not p: a face released in uniaxial strain (sigma_nn = 0, the deviator
      // reverse-yielded to s_nn = p = 2Y/3) still pushed across with p, and parted in tension.
      double tOwn = p_[r.i], tOther = p_[j];
      if constexpr (Solid) {
        const double inv = 1.0 / p.r2;
        tOwn -= p.xij.dot(r.SiOwn * p.xij) * inv * (product_ ? r.rhoi : r.rhoi * r.rhoi);
        tOther -= p.xij.dot(sOverRho_[j] * p.xij) * inv * (product_ ? rhoj : rhoj * rhoj);
      }
      const double pOwn = std::max(tOwn, 0.0), pOther = std::max(tOther, 0.0);
      p.qOwn = product_ ? pOwn : pOwn / (r.rhoi * r.rhoi);
      p.qOther = product_ ? pOther : pOther / (rhoj * rhoj);
    }
    p.sij = r.sI * scratch_[j].s; // 1, or 1/(rho_i rho_j)
  }

  // rz: the pair's momentum and energy terms weigh Rbar/R_i (solvers/Axisymmetric.hpp); k_r
  // sums the part the weight adds, for the hoop force (closeRow).
  [[gnu::always_inline]] void axisymmetricWeight(Row& r, Pair& p) const {
    const std::uint32_t j = p.j;
    p.mj = m_[j], p.wVol = scratch_[j].vol, p.w = 1.0;
    if constexpr (Dim == 2)
      if (rz_) {
        p.w = rz::pairWeight(ring_[r.i], ring_[j]);
        const double k = p.mj * (p.w - 1.0) * scratch_[j].s * p.gI[0];
        r.kr += k;
        if (p.across) r.krAcross += k;
        p.mj *= p.w;
        p.wVol *= p.w;
      }
  }

  // The pressure and the viscosity: Lam et al. (2001) Eq. 20's isotropic part
  // (pair::pressureTerm), with both particles' own gradients when corrected.
  [[gnu::always_inline]] void pressureForce(Row& r, const Pair& p) const {
    if constexpr (Corrected) {
      r.ai.noalias() -=
          p.mj * ((p.qOwn * p.sij) * p.gI + (p.qOther * p.sij) * p.gJ + p.Pij * p.gradW);
    } else if constexpr (Solid) {
      r.ai.noalias() -= (p.mj * pair::pressureTerm(p.qOwn, p.qOther, p.sij, p.Pij)) * p.gradW;
    } else {
      // (The hydro loop keeps the division of the product form behind a branch: it spills
      // less there than the factor s_i s_j, the solid loops the other way round.)
      const double term =
          (product_ ? (p.qOwn + p.qOther) / (r.rhoi * rho_[p.j]) : p.qOwn + p.qOther) + p.Pij;
      r.ai.noalias() -= (p.mj * term) * p.gradW;
    }
  }

  // A confining pressure (methods/modules/ConfiningPressure.hpp): the row's surface sum G_i, the
  // force per unit mass a unit shift of the stress of i and all its neighbors exerts on i.
  [[gnu::always_inline]] void surfaceSums(Row& r, const Pair& p) const {
    if (!surfaces_) return;
    const double rhoj = rho_[p.j];
    const double uJ = product_ ? 1.0 : 1.0 / (rhoj * rhoj);
    if constexpr (Corrected)
      r.Gi.noalias() += (p.mj * p.sij) * (r.uI * p.gI + uJ * p.gJ);
    else
      r.Gi.noalias() += (p.mj * (r.uI + uJ) * p.sij) * p.gradW;
  }

  // sigma = -p I + S: the deviatoric part of Lam et al. Eqs. 20-21 in tensor form; the energy
  // share is -S_i/rho_i^2 : (m_j v_ij (x) grad W), which with the momentum term conserves total
  // energy pair by pair. rho^2 form: (S_i/rho_i^2 + S_j/rho_j^2) grad W; product form: the same
  // with S/rho on both sides, each times the other's s = 1/rho. And the velocity gradient
  // L_i = -sum_j V_j v_ij (x) grad_i W_ij.
  // (Each dimension in the form that compiles to the arithmetic the rho^2 form had as an
  // instantiation of its own, so that earlier runs are reproduced bit for bit: in 1D the other's
  // s applied to the gradient, a factor 1 there; in 2D and 3D a branch, which keeps the loop's
  // registers from spilling.)
  [[gnu::always_inline]] void deviatoricStress(Row& r, const Pair& p) const {
    const std::uint32_t j = p.j;
    if constexpr (Dim == 1) {
      const Vec<Dim> tI = r.SiOwn * (scratch_[j].s * p.gI), tJ = sOverRho_[j] * (r.sI * p.gJ);
      r.ai.noalias() += p.mj * (tI + tJ);
      r.dei -= p.mj * p.vij.dot(tI);
    } else {
      const Vec<Dim> tI = r.SiOwn * p.gI, tJ = sOverRho_[j] * p.gJ;
      if (product_) {
        r.ai.noalias() += p.wVol * tI + (p.mj * r.sI) * tJ;
        r.dei -= p.wVol * p.vij.dot(tI);
      } else {
        r.ai.noalias() += p.mj * (tI + tJ);
        r.dei -= p.mj * p.vij.dot(tI);
      }
    }
    r.Li.noalias() -= scratch_[j].vol * (p.vij * p.gI.transpose());
    if constexpr (Dim == 2)
      if (rz_) r.Mrr -= scratch_[j].vol * p.xij[0] * p.gI[0];
  }

  // Gray, Monaghan & Swift (2001) (Monaghan 2000 for fluids): m_j f_ij^n (R_i + R_j) . grad W in
  // the momentum equation; e_i takes its own share, -m_j f^n v_ij . R_i grad W, so that total
  // energy stays conserved pair by pair (as for the stress). Only where one of the two is in
  // tension (R != 0): a body compressed in every direction skips it; a flowing bar has a tensile
  // principal stress (the hoop) almost everywhere, so over a Taylor bar this saves 1%.
  [[gnu::always_inline]] void artificialStress(Row& r, const Pair& p) const {
    const std::uint32_t j = p.j;
    if (!(artificial_ && (r.tensileI || tensile_[j]))) return;
    const double f = K::f(p.qMean) * invWdp_;
    double fn = f;
    for (int k = 1; k < nAS_; ++k) fn *= f;
    const Vec<Dim> rI = r.Ri * p.gI;
    r.ai.noalias() += (p.mj * fn) * (rI + R_[j] * p.gJ);
    r.dei -= p.mj * fn * p.vij.dot(rI);
    // rz: R has no hoop part to balance what the weight adds (~ 2 R.k), so the radial part of
    // that is taken off per particle (closeRow), as the hoop force does for sigma: else a
    // uniform tension pulls the rings next to the axis inward (by half their speed in a uniform
    // radial stretch).
    if constexpr (Dim == 2)
      if (rz_) r.krAS += m_[j] * (p.w - 1.0) * fn * p.gI[0];
  }

  // Each particle takes its own p dV share of the pair's work and half the viscous heating: e_i
  // gains (p_i/rho_i^2 + Pi_ij/2) m_j v_ij . grad W (Monaghan 1992), or p_i/(rho_i rho_j) in the
  // product form. Summed over pairs this equals Lam et al.'s symmetric Eq. 21 (total energy is
  // conserved exactly either way), but Eq. 21's even split charges a cold particle for the work
  // of a hot neighbour pushing it away, which drives e negative around a point blast (Sedov: e
  // down to -60 at 20 steps).
  [[gnu::always_inline]] void energyShare(Row& r, const Pair& p) const {
    const double own = p.qOwn * p.sij;
    if constexpr (Corrected)
      r.dei += p.mj * (own * p.vij.dot(p.gI) + 0.5 * p.Pij * p.vgrad);
    else
      r.dei += p.mj * (own + 0.5 * p.Pij) * p.vgrad;
  }

  // Continuity, -div v_i = sum_j V_j v_ij . grad W(r_ij, h_i) (closeRow's comment says why this
  // form); the corrected gradient's trace where corrected, exact for a linear field. An open
  // crack is not the material's expansion: a cracked pair is left out of the divergence, as out
  // of the velocity gradient. Pairs across a contact are summed apart (contactStrain).
  [[gnu::always_inline]] void continuity(Row& r, const Pair& p) const {
    if (p.cracked) return;
    const double volj = scratch_[p.j].vol;
    if (p.across) {
      contactPair(r, p, volj);
    } else {
      r.drhoi += volj * p.vij.dot(Corrected ? p.gI : p.gradWi);
    }
    if constexpr (Dim == 2)
      if (rz_) r.MrrVolume -= volj * p.xij[0] * (Corrected ? p.gI[0] : p.gradWi[0]);
  }

  // A pair across a contact: the normal part of v_ij only (a frictionless contact slides, and
  // sliding is no strain), as -div v and as the stretching (v_ij . n) n (x) grad W it is in L;
  // an approach always, a parting while i's normal stress along the pair is compressive.
  [[gnu::always_inline]] void contactPair(Row& r, const Pair& p, double volj) const {
    const Vec<Dim> n = p.xij / std::sqrt(p.r2);
    const double vn = volj * p.vij.dot(n);
    const double c = vn * n.dot(Corrected ? p.gI : p.gradWi);
    if (c > 0.0 || normalStress(r.i, p) < 0.0) {
      r.drhoAcross += c;
      if constexpr (Solid) r.LAcross.noalias() -= vn * (n * p.gI.transpose());
    }
    const double dij = 0.5 * (root<Dim>(scratch_[r.i].vol) + root<Dim>(volj));
    r.nearAcross2 = std::min(r.nearAcross2, p.r2 / (dij * dij));
  }

  // A body's particle starts at the deck's density with only its own body in its kernel, so
  // the strain its pairs across a contact read is its own only once the bodies touch: summed
  // while a gap closes, the other body's share of the kernel counts twice (one spacing of gap
  // in front of a 400 m/s aluminium flyer doubled the face's 3.1 GPa, five made it 15 GPa) and
  // the parting reads it back as tension (it failed the target behind its impact face). So the
  // pairs count once the nearest particle across is within 1.25 mean spacings, d_ij = (V_i^(1/D)
  // + V_j^(1/D))/2 (touching lattices offset by half a spacing sideways are 1.12 d apart in 2D,
  // 1.22 in 3D); a parting pair only while i's normal stress along it is compressive (a contact
  // carries no tension: once the face is released, parting is a gap opening). They enter L as
  // they enter the density, or the face's deviator leaves the uniaxial path its density takes
  // (released to p = 0 with 46 MPa of tension in sigma_nn).
  [[gnu::always_inline]] void contactStrain(Row& r) const {
    if (!(r.nearAcross2 <= kTouching * kTouching)) return;
    r.drhoi += r.drhoAcross;
    if constexpr (Solid) r.Li += r.LAcross;
  }
  // i's normal stress along the pair, n . sigma_i . n with n = x_ij/r_ij.
  double normalStress(std::size_t i, const Pair& p) const {
    double snn = -p_[i];
    if constexpr (Solid)
      snn += p.xij.dot(Sdev_[i].template topLeftCorner<Dim, Dim>() * p.xij) / p.r2;
    return snn;
  }
  static constexpr double kTouching = 1.25;

  // Balsara (1995): div v and |curl v| for the next loop's switch (pair::balsaraFactor).
  [[gnu::always_inline]] void balsaraSums(Row& r, const Pair& p) const {
    if (!balsara_) return;
    const double volj = scratch_[p.j].vol;
    r.divi -= volj * p.vgrad;
    if constexpr (Dim == 2) r.curli[0] += volj * (p.vij[0] * p.gradW[1] - p.vij[1] * p.gradW[0]);
    if constexpr (Dim == 3) r.curli += volj * p.vij.cross(p.gradW);
  }

  // ---- the row ----------------------------------------------------------------------------
  [[gnu::always_inline]] void openRow(Row& r, std::size_t i) const {
    r.i = i;
    r.xi = x_[i], r.vi = v_[i];
    r.hi = h_[i], r.rhoi = rho_[i], r.ci = cs_[i];
    r.bodyi = body_[i];
    const RowScratch& ri = scratch_[i];
    r.qI = ri.q, r.sI = ri.s, r.fi = ri.balsara;
    r.uI = product_ ? 1.0 : 1.0 / (r.rhoi * r.rhoi);
    r.ai.setZero(), r.Gi.setZero();
    r.dei = 0.0, r.drhoi = 0.0, r.sumWHi = 0.0, r.mui = 0.0, r.divi = 0.0;
    r.drhoAcross = 0.0;
    r.nearAcross2 = std::numeric_limits<double>::infinity();
    r.curli.setZero();
    r.Mrr = 1.0, r.MrrVolume = 0.0, r.kr = 0.0, r.krAcross = 0.0, r.krAS = 0.0, r.Dtt = 0.0;
    if constexpr (Solid) {
      r.SiOwn = sOverRho_[i].full();
      r.Li.setZero();
      r.LAcross.setZero();
      r.Mrr = 0.0;
      r.Ri = artificial_ ? R_[i].full() : MatD::Zero();
    }
    r.tensileI = Solid && artificial_ && tensile_[i];
    if constexpr (Corrected) r.Bi = Bcorr_[i].template topLeftCorner<Dim, Dim>();
  }

  // The kernel values of the row's pairs, in a pass of their own that runs in vector registers
  // (Sph::pairKernels, Sph::anisoPairKernels).
  [[gnu::always_inline]] void kernelPass(const Row& r, std::span<const std::uint32_t> row,
                                         RowKernels& kernels) const {
    const Vec<Dim> xi = r.xi; // (a copy: the call takes its address, not the row's)
    if constexpr (Aniso) {
      o_.anisoPairKernels(xi, r.i, row, kernels);
    } else {
      const double hiInv = 1.0 / r.hi;
      o_.pairKernels(xi, hiInv, sigma_ * ipow<Dim>(hiInv) * hiInv, row, kernels);
    }
  }

  // The hoop force and rates (solvers/Axisymmetric.hpp), the confining pressure's force, and
  // the row's writes.
  [[gnu::always_inline]] void closeRow(Row& r) const {
    const std::size_t i = r.i;
    if (frictionless_) contactStrain(r);
    if constexpr (Dim == 2)
      if (rz_) hoopClosure(r);
    if (surfaces_) {
      // rz: the hoop force's share, -2 c k_r per unit sigma_tt (rz::hoopForce).
      if constexpr (Dim == 2)
        if (rz_) r.Gi[0] -= 2.0 * (product_ ? 1.0 / r.rhoi : 1.0 / (r.rhoi * r.rhoi)) * r.kr;
      r.ai.noalias() += P_[i] * r.Gi;
      area_[i] = -mass_[i] * r.Gi;
    }
    acc_[i] = r.ai;
    dedt_[i] = r.dei;
    if constexpr (Solid) {
      Lgrad_[i].setZero();
      Lgrad_[i].template topLeftCorner<Dim, Dim>() = r.Li;
      if constexpr (Dim == 2) Lgrad_[i](2, 2) = r.Dtt; // the hoop rate in rz (0 in plane strain)
    }
    // Continuity, d rho_i/dt = -rho_i div v_i with div v_i = -sum_j (m_j/rho_j) v_ij . grad
    // W(r_ij, h_i): volume-weighted, so it stays accurate across a material interface with a
    // large density jump, and with i's own support (gather), so that it stays consistent where h
    // changes fast. (The pair-averaged gradient of the momentum equation over-compresses the Noh
    // shock by ~40% here; the gather form gives the post-shock density within 8%.)
    drhodt_[i] = r.rhoi * r.drhoi;
    sumWH_[i] = r.sumWHi;
    muMax_[i] = r.mui;
    if (balsara_) {
      // Not into divv/curlv yet: later rows of this loop read them of their owned neighbors,
      // which must see the previous loop's values, as ghosts do (else the result depends on
      // the row order, and so on the rank count).
      o_.divNew_[i] = r.divi;
      o_.curlNew_[i] = r.curli.norm();
    }
  }

  // rz: the hoop force is the complement of the pair weights, pair by pair: where a pair carries
  // -max(p_i, 0) I of i's stress (across a contact or a crack), its share of the hoop force
  // carries the same. Else a ring whose pairs are all cracked, in tension, has a hoop pull no
  // radial stress balances and no hoop rate relaxes (its density is frozen): it falls toward
  // the axis, its p dV work drives e, and with it the tension, down without bound (a steel ring
  // among eroded tungsten reached -3e14 Pa).
  [[gnu::always_inline]] void hoopClosure(Row& r) const {
    const std::size_t i = r.i;
    const double sigmaTT = (Solid ? Sdev_[i](2, 2) : 0.0) - p_[i];
    const rz::HoopForce hoop =
        rz::hoopForce(r.kr - r.krAcross, sigmaTT, -std::max(p_[i], 0.0), r.krAcross,
                      product_ ? 1.0 / r.rhoi : 1.0 / (r.rhoi * r.rhoi), r.vi[0]);
    r.ai[0] += hoop.ar;
    r.dei += hoop.dedt;
    if constexpr (Solid)
      if (r.tensileI) { // (else R_i = 0)
        const double ar = -2.0 * r.Ri(0, 0) * r.krAS;
        r.ai[0] += ar;
        r.dei -= ar * r.vi[0];
      }
    const rz::HoopRates D =
        rz::hoopRates(r.vi[0], ring_[i], r.MrrVolume, Solid ? r.Mrr : r.MrrVolume);
    r.drhoi -= D.volume;
    r.divi += D.volume;
    r.Dtt = D.strain;
  }

  // The kernels' pair predicate (reaches), for the crack rule.
  bool interacts(std::size_t a, std::size_t b) const {
    if constexpr (Aniso)
      return reaches<Dim>(x_[a] - x_[b], o_.anisoRow_[a].G, o_.anisoRow_[b].G, K::support);
    else
      return reaches<Dim>(x_[a] - x_[b], std::max(h_[a], h_[b]), K::support);
  }

  // ---- what depends on j alone, of every row (ghosts included), once a loop ----------------
  // The pair loop then only adds and multiplies (solvers/SphRatesLoopRows.hpp).
  void prepareRows();
  void prepareStressRows();
  void prepareRowScratch();

  Sph& o_;
  const neighbors::NeighborList& nl_;
  const std::size_t firstWallImage_;
  // Inputs: fields of every row (ghosts included), m as the planar loops weigh it
  // (Sph::planarMass).
  const std::span<Vec<Dim>> x_, v_;
  const std::span<double> h_;
  const std::span<const double> m_;
  const std::span<double> rho_, p_, cs_, mass_;
  const std::size_t n_;          // owned rows
  std::span<std::int32_t> body_; // contact groups, or bodies when welded
  std::span<Tensor<3>> Sdev_, Lgrad_, Bcorr_;
  const RowScratch* scratch_ = nullptr;
  const RowTensor* sOverRho_ = nullptr;
  const RowTensor* R_ = nullptr;          // artificial stress
  const std::uint8_t* tensile_ = nullptr; // R != 0
  const double* ring_ = nullptr;          // rz: ring radii
  std::span<double> P_;                   // confining pressure
  // Outputs, of the owned rows.
  std::span<Vec<Dim>> acc_, area_;
  std::span<double> dedt_, drhodt_, sumWH_, muMax_;
  // Options.
  bool balsara_ = false, product_ = false, rz_ = false, artificial_ = false;
  bool reconstruct_ = false, frictionless_ = false, surfaces_ = false, damagedPairs_ = false;
  int nAS_ = 1;
  double invWdp_ = 1.0, alpha_ = 0.0, beta_ = 0.0, sigma_ = 0.0;
  double qc_ = 0.0; // 1/n_h: a pair's mean spacing in units of h (the close-pair guard)
};

template <int Dim, class K, bool Aniso>
template <Stress Mode>
void Sph<Dim, K, Aniso>::ratesLoop(const neighbors::NeighborList& nl, std::size_t firstWallImage) {
  RatesLoop<Mode>(*this, nl, firstWallImage).run();
}

} // namespace spall::solvers::sph

#include "SphRatesLoopRows.hpp"
