#pragma once
// SPH's and ASPH's force loop: the rates of every owned particle from its neighbors (the
// declaration's comment in Sph.hpp says what it computes and why).
#include "Sph.hpp"

namespace spall::solvers::sph {

template <int Dim, class K, bool Aniso>
template <Stress Mode>
void Sph<Dim, K, Aniso>::ratesLoop(const neighbors::NeighborList& nl, std::size_t firstWallImage) {
  constexpr bool Solid = Mode != Stress::Pressure;
  constexpr bool Corrected = Mode == Stress::CorrectedCauchy;
  // The kernel values of a row come from a pass of their own before its pairs, which runs in
  // vector registers (Sph::pairKernels, Sph::anisoPairKernels; their gains: decks/README, "ASPH").
  using MatD = Tensor<Dim>;
  const auto x = s_[f_.x];
  const auto v = s_[f_.v];
  const auto h = s_[f_.h];
  const auto m = planarMass();
  const auto rho = s_[f_.rho];
  const auto p = s_[f_.p];
  const auto cs = s_[f_.cs];
  const auto acc = s_[f_.a];
  const auto dedt = s_[f_.dedt];
  const auto drhodt = s_[f_.drhodt];
  const auto sumWH = s_[f_.sumWH];
  const auto muMax = s_[f_.muMax];
  const bool balsara = cfg_.artificial_viscosity.balsara;
  const bool product = cfg_.stress_form == StressForm::RhoProduct;
  [[maybe_unused]] const bool rz = cfg_.geometry == Geometry::RZ;
  const auto divv = balsara ? s_[f_.divv] : std::span<double>{};
  const auto curlv = balsara ? s_[f_.curlv] : std::span<double>{};
  if (balsara)
    resizeWithHeadroom(divNew_, s_.localCount()), resizeWithHeadroom(curlNew_, s_.localCount());
  const auto Sdev = Solid ? s_[f_.S] : std::span<Tensor<3>>{};
  const auto Lgrad = Solid ? s_[f_.L] : std::span<Tensor<3>>{};
  // S_j / rho_j^2 (or S_j / rho_j for the product form) of every row, ghosts included, once:
  // the pair loop then only adds and multiplies.
  [[maybe_unused]] const bool artificialStress = cfg_.artificial_stress.enabled;
  [[maybe_unused]] const bool reconstruct = Solid && cfg_.artificial_viscosity.reconstruct;
  const auto Bcorr = Corrected ? s_[f_.B] : std::span<Tensor<3>>{};
  [[maybe_unused]] const int nAS = cfg_.artificial_stress.exponent;
  // f_ij = W(r_ij)/W(dp) with dp = h/n_h, the initial spacing in units of h.
  [[maybe_unused]] const double invWdp = 1.0 / K::f(1.0 / cfg_.nodes_per_h);
  if constexpr (Solid) {
    resizeWithHeadroom(sOverRho_, s_.size());
#pragma omp parallel for schedule(static) if (threaded(s_.size()))
    for (std::size_t j = 0; j < s_.size(); ++j)
      sOverRho_[j] = RowTensor::symmetricPart(Sdev[j]) / (product ? rho[j] : rho[j] * rho[j]);
    // The strain rates of the reconstruction, of every row before this loop overwrites L (the
    // owned rows must read the previous loop's L, as ghosts do: else the sums depend on the
    // row order, and so on the rank count).
    if (reconstruct) {
      resizeWithHeadroom(strainRate_, s_.size());
      resizeWithHeadroom(isochoric_, s_.size());
#pragma omp parallel for schedule(static) if (threaded(s_.size()))
      for (std::size_t j = 0; j < s_.size(); ++j) {
        const MatD Lj = Lgrad[j].template topLeftCorner<Dim, Dim>();
        strainRate_[j] = RowTensor::symmetricPart(Lj);
        // In rz the volume change includes the hoop rate D_tt = L(2,2): a mushroom's plastic
        // flow is isochoric in 3D, not in the r-z plane.
        isochoric_[j] = rz ? pair::isochoricGate<3>(0.5 * (Lgrad[j] + Lgrad[j].transpose()))
                           : pair::isochoricGate<Dim>(strainRate_[j].full());
      }
    }
    if (artificialStress) {
      resizeWithHeadroom(artificialStress_, s_.size());
      resizeWithHeadroom(tensile_, s_.size());
      // Only solids: a fluid in a multi-material deck keeps the plain pressure term.
      const auto mat = s_[f_.material];
#pragma omp parallel for schedule(static) if (threaded(s_.size()))
      for (std::size_t j = 0; j < s_.size(); ++j) {
        artificialStress_[j] = solid_[static_cast<std::size_t>(mat[j])]
                                   ? RowTensor::symmetricPart(pair::artificialStress<Dim>(
                                         Sdev[j], p[j], rho[j], cfg_.artificial_stress.epsilon))
                                   : RowTensor::zero();
        tensile_[j] = artificialStress_[j].nonzero();
      }
    }
  }
  const double alpha = cfg_.artificial_viscosity.alpha, beta = cfg_.artificial_viscosity.beta;
  const double sigma = K::sigma();
  const std::size_t n = s_.localCount();
  const bool frictionless = cfg_.contact != Contact::Welded;
  const auto body = frictionless ? s_[f_.contactGroup] : s_[f_.body];
  // A confining pressure (methods/modules/ConfiningPressure.hpp): each row's surface sum G_i,
  // the force per unit mass a unit shift of the stress of i and all its neighbors exerts on i.
  const bool surfaces = f_.surfaceArea.valid();
  const auto P = surfaces ? s_[f_.confiningPressure] : std::span<double>{};
  const auto area = surfaces ? s_[f_.surfaceArea] : std::span<Vec<Dim>>{};
  const auto mass = s_[f_.m];
  // What the pair loop needs of a neighbor j that depends on j alone, once per row and packed
  // together: the pair loop is left with one division (1/r) and one square root.
  if constexpr (Aniso) prepareAnisoRows();
  [[maybe_unused]] const auto cellMoment = Aniso ? s_[f_.cellMoment] : std::span<Tensor<Dim>>{};
  [[maybe_unused]] const auto cellAge = Aniso ? s_[f_.cellAge] : std::span<std::int32_t>{};
  [[maybe_unused]] const auto id = s_[f_.id];
  [[maybe_unused]] const std::int32_t shapeInterval = cfg_.shape_interval;
  // The pair term's form and the Balsara switch enter as per-row factors, so that the pair
  // loop has no branch on them: q = p/rho^2 and s = 1 (rho^2 form) or q = p and s = 1/rho
  // (product form), the pressure term being (q_i + q_j) s_i s_j; f = the Balsara factor, or 1.
  // (A multiplication by exactly 1 changes no bit: the rho^2 form without Balsara computes what
  // it computed when each was an instantiation of its own.)
  resizeWithHeadroom(rowScratch_, s_.size());
#pragma omp parallel for schedule(static) if (threaded(s_.size()))
  for (std::size_t j = 0; j < s_.size(); ++j) {
    const double hjInv = 1.0 / h[j];
    rowScratch_[j] = {hjInv,
                      sigma * ipow<Dim>(hjInv) * hjInv,
                      m[j] / rho[j],
                      product ? p[j] : p[j] / (rho[j] * rho[j]),
                      product ? 1.0 / rho[j] : 1.0,
                      balsara ? pair::balsaraFactor(divv[j], curlv[j], cs[j], h[j]) : 1.0};
  }

  // Damaged pairs (solvers/CrackedPairs.hpp): a pair with a particle that failed (damage 1) and
  // can carry no tension, or with one between them, transmits compression only, as across a
  // contact: an intact neighbor cannot pull on it, and it pulls on nothing (the crack is open).
  // Without it, the intact side's tension would still reach across the failed layer through
  // the pair's other half.
  const bool damagedPairs = Solid && markCracks();
  if (damagedPairs) cracks_.collect(nl, n);
  [[maybe_unused]] const auto interacts = [&](std::size_t a, std::size_t b) {
    if constexpr (Aniso)
      return reaches<Dim>(x[a] - x[b], anisoRow_[a].G, anisoRow_[b].G, K::support);
    else
      return reaches<Dim>(x[a] - x[b], std::max(h[a], h[b]), K::support);
  };

  // Rows in parallel (core/Threads.hpp): each writes only its own rates, from its neighbors'
  // inputs in its list's order; chunks of rows handed out as threads free up (rows differ in
  // neighbor count and in how many pairs approach).
#pragma omp parallel for schedule(dynamic, 64) if (threaded(n))
  for (std::size_t i = 0; i < n; ++i) {
    const Vec<Dim> xi = x[i], vi = v[i];
    const double hi = h[i], hiInv = 1.0 / hi;
    const double gradNormI = sigma * ipow<Dim>(hiInv) * hiInv;
    thread_local std::vector<std::uint32_t> rowBuf; // each thread's own
    const auto row = nl.of(i, rowBuf);
    [[maybe_unused]] thread_local PairKernels kernelRow; // each thread's own
    if constexpr (!Aniso) pairKernels(xi, hiInv, gradNormI, row, kernelRow);
    [[maybe_unused]] thread_local AnisoPairKernels anisoKernelRow; // each thread's own
    if constexpr (Aniso) anisoPairKernels(xi, i, row, anisoKernelRow);
    const double rhoi = rho[i], ci = cs[i];
    const std::int32_t bodyi = body[i];
    const RowScratch& ri = rowScratch_[i];
    const double qI = ri.q, sI = ri.s, fi = ri.balsara;
    Vec<Dim> ai = Vec<Dim>::Zero(), Gi = Vec<Dim>::Zero();
    const double uI = product ? 1.0 : 1.0 / (rhoi * rhoi); // q of a unit pressure
    double dei = 0.0, drhoi = 0.0, sumWHi = 0.0, mui = 0.0, divi = 0.0;
    [[maybe_unused]] Eigen::Matrix<double, Dim == 3 ? 3 : 1, 1> curli;
    curli.setZero();
    // Solids: S_i / rho_i^2 (or S_i / rho_i for the product form) in the Dim x Dim block, and the
    // velocity gradient L_i = -sum_j (m_j/rho_j) v_ij (x) grad_i W_ij. The row's own tensors
    // as full ones: kept as SymTensor here, taylor_bar_3d's step took 25% longer.
    [[maybe_unused]] MatD SiOwn, Ri, Li, Bi;
    // rz: -sum_j V_j x_ij,r g_ij,r with the velocity gradient's and the divergence's kernel
    // gradients, the normalisation the hoop rate is given (solvers/Axisymmetric.hpp).
    // k_r's share from pairs across a contact or crack (krAcross), where i's own stress enters
    // the pair term as -max(p_i, 0) I only.
    [[maybe_unused]] double Mrr = 1.0, MrrVolume = 0.0, kr = 0.0, krAcross = 0.0, krAS = 0.0;
    if constexpr (Solid) {
      SiOwn = sOverRho_[i].full(); // S_i/rho_i^2, or S_i/rho_i for the product form
      Li.setZero();
      Mrr = 0.0;
      Ri = artificialStress ? artificialStress_[i].full() : MatD::Zero();
    }
    // A pair adds artificial stress only if one of the two is in tension (R != 0). A body
    // compressed in every direction skips it; a flowing bar has a tensile principal stress (the
    // hoop) almost everywhere, so over a Taylor bar this saves 1% (decks/README, the cost).
    [[maybe_unused]] const bool tensileI = Solid && artificialStress && tensile_[i];
    if constexpr (Corrected) Bi = Bcorr[i].template topLeftCorner<Dim, Dim>();
    [[maybe_unused]] ReconstructionRow reconRow;
    if constexpr (Solid)
      if (reconstruct) reconRow = reconstructionRow(i);

    for (std::size_t k = 0; k < row.size(); ++k) {
      const std::uint32_t j = row[k];
      const Vec<Dim> xij = xi - x[j];
      const double r2 = xij.squaredNorm();
      if (r2 == 0.0) continue; // coincident particles exert no force on each other
      const RowScratch& rj = rowScratch_[j];
      // The pair's gradient (average of both supports'), i's own one (continuity), and the
      // mean smoothing scale along the pair (viscosity): h, or r/eta for ASPH, where r itself
      // is needed only then (the kernels work in eta).
      Vec<Dim> gradW, gradWi;
      [[maybe_unused]] double hbarOverR = 0.0;
      [[maybe_unused]] double qMean; // the pair's mean normalised distance
      if constexpr (Aniso) {
        const AnisoPairKernels& pk = anisoKernelRow;
        if (pk.coincident[k] != 0.0) continue; // coincident in eta (underflow)
        for (int d = 0; d < Dim; ++d) gradWi[d] = pk.gWi(d, k), gradW[d] = pk.gW(d, k);
        hbarOverR = pk.hbarOverR[k];
        qMean = pk.qMean[k];
        sumWHi += pk.wH[k];
      } else {
        gradW = kernelRow.gW[k] * xij;
        gradWi = kernelRow.gWi[k] * xij;
        qMean = kernelRow.qMean[k];
        sumWHi += kernelRow.wH[k];
      }
      // The gradients i's and j's own quantities are contracted with (the same unless
      // corrected).
      Vec<Dim> gI = gradW, gJ = gradW;
      if constexpr (Corrected) {
        gI = Bi * gradW;
        gJ = Bcorr[j].template topLeftCorner<Dim, Dim>() * gradW;
      }

      const Vec<Dim> vij = vi - v[j];
      // A rigid wall's image exerts no viscosity (Boundaries::holdAcceleration holds the wall).
      double vr = j < firstWallImage ? vij.dot(xij) : 0.0;
      double Pij = 0.0;
      if constexpr (Solid)
        if (reconstruct && vr < 0.0) vr = reconstructedApproach(vr, xij, reconRow, j, qMean);
      if (vr < 0.0) {
        // Monaghan & Gingold (1983) viscosity (Lam et al. 2001, Eqs. 22-24).
        const double hbar = Aniso ? hbarOverR * std::sqrt(r2) : 0.5 * (hi + h[j]);
        double mu;
        Pij = pair::viscosity(vr, r2, hbar, 0.5 * (ci + cs[j]), 0.5 * (rhoi + rho[j]), alpha, beta,
                              mu);
        Pij *= 0.5 * (fi + rj.balsara); // exactly 1 without the switch
        mui = std::max(mui, -mu);
      }
      const double rhoj = rho[j];
      // Frictionless contact between bodies (contact groups): across a group boundary only
      // compression is transmitted (no tension, no shear), so bodies can slide and separate.
      const bool cracked =
          damagedPairs && cracks_.cracked(i, j, std::span<const Vec<Dim>>(x), interacts);
      const bool across = (frictionless && body[j] != bodyi) || cracked;
      double qOwn = qI, qOther = rj.q;
      if (across) {
        const double pOwn = std::max(p[i], 0.0), pOther = std::max(p[j], 0.0);
        qOwn = product ? pOwn : pOwn / (rhoi * rhoi);
        qOther = product ? pOther : pOther / (rhoj * rhoj);
      }
      const double sij = sI * rj.s; // 1, or 1/(rho_i rho_j)
      // rz: the pair's momentum and energy terms weigh Rbar/R_i (solvers/Axisymmetric.hpp);
      // k_r sums the part the weight adds, for the hoop force.
      double mj = m[j], wVol = rj.vol;
      [[maybe_unused]] double w = 1.0;
      if constexpr (Dim == 2)
        if (rz) {
          w = rz::pairWeight(ringR_[i], ringR_[j]);
          const double k = mj * (w - 1.0) * rj.s * gI[0];
          kr += k;
          if (across) krAcross += k;
          mj *= w;
          wVol *= w;
        }
      if constexpr (Corrected) {
        ai.noalias() -= mj * ((qOwn * sij) * gI + (qOther * sij) * gJ + Pij * gradW);
      } else if constexpr (Solid) {
        ai.noalias() -= (mj * pair::pressureTerm(qOwn, qOther, sij, Pij)) * gradW;
      } else {
        // (The hydro loop keeps the division of the product form behind a branch: it spills
        // less there than the factor s_i s_j, the solid loops the other way round.)
        const double term = (product ? (qOwn + qOther) / (rhoi * rhoj) : qOwn + qOther) + Pij;
        ai.noalias() -= (mj * term) * gradW;
      }
      if (surfaces) {
        const double uJ = product ? 1.0 : 1.0 / (rhoj * rhoj);
        if constexpr (Corrected)
          Gi.noalias() += (mj * sij) * (uI * gI + uJ * gJ);
        else
          Gi.noalias() += (mj * (uI + uJ) * sij) * gradW;
      }
      const double vgrad = vij.dot(gradW);
      if constexpr (Solid)
        if (!across) {
          // sigma = -p I + S: the deviatoric part of Lam et al. Eqs. 20-21 in tensor form; the
          // energy share is -S_i/rho_i^2 : (m_j v_ij (x) grad W), which with the momentum term
          // conserves total energy pair by pair.
          // rho^2 form: (S_i/rho_i^2 + S_j/rho_j^2) grad W; product form: the same with
          // S/rho on both sides, each times the other's s = 1/rho.
          // (Each dimension in the form that compiles to the arithmetic the rho^2 form had
          // as an instantiation of its own, so that earlier runs are reproduced bit for bit:
          // in 1D the other's s applied to the gradient, a factor 1 there; in 2D and 3D a
          // branch, which keeps the loop's registers from spilling.)
          if constexpr (Dim == 1) {
            const Vec<Dim> tI = SiOwn * (rj.s * gI), tJ = sOverRho_[j] * (sI * gJ);
            ai.noalias() += mj * (tI + tJ);
            dei -= mj * vij.dot(tI);
          } else {
            const Vec<Dim> tI = SiOwn * gI, tJ = sOverRho_[j] * gJ;
            if (product) {
              ai.noalias() += wVol * tI + (mj * sI) * tJ;
              dei -= wVol * vij.dot(tI);
            } else {
              ai.noalias() += mj * (tI + tJ);
              dei -= mj * vij.dot(tI);
            }
          }
          Li.noalias() -= rj.vol * (vij * gI.transpose());
          if constexpr (Dim == 2)
            if (rz) Mrr -= rj.vol * xij[0] * gI[0];
          if (artificialStress && (tensileI || tensile_[j])) {
            // Gray, Monaghan & Swift (2001) (Monaghan 2000 for fluids): m_j f_ij^n (R_i + R_j) .
            // grad W in the momentum equation; e_i takes its own share, -m_j f^n v_ij . R_i grad
            // W, so that total energy stays conserved pair by pair (as for the stress).
            const double f = K::f(qMean) * invWdp;
            double fn = f;
            for (int k = 1; k < nAS; ++k) fn *= f;
            const Vec<Dim> rI = Ri * gI;
            ai.noalias() += (mj * fn) * (rI + artificialStress_[j] * gJ);
            dei -= mj * fn * vij.dot(rI);
            // rz: R has no hoop part to balance what the weight adds (~ 2 R.k), so the radial
            // part of that is taken off per particle below, as the hoop force does for sigma:
            // else a uniform tension pulls the rings next to the axis inward (by half their
            // speed in a uniform radial stretch).
            if constexpr (Dim == 2)
              if (rz) krAS += m[j] * (w - 1.0) * fn * gI[0];
          }
        }
      // Each particle takes its own p dV share of the pair's work and half the viscous
      // heating: e_i gains (p_i/rho_i^2 + Pi_ij/2) m_j v_ij . grad W (Monaghan 1992), or
      // p_i/(rho_i rho_j) in the product form. Summed over pairs this equals Lam et al.'s
      // symmetric Eq. 21 (total energy is conserved exactly either way), but Eq. 21's even
      // split charges a cold particle for the work of a hot neighbour pushing it away, which
      // drives e negative around a point blast (Sedov: e down to -60 at 20 steps).
      const double own = qOwn * sij;
      if constexpr (Corrected)
        dei += mj * (own * vij.dot(gI) + 0.5 * Pij * vgrad);
      else
        dei += mj * (own + 0.5 * Pij) * vgrad;
      const double volj = rj.vol;
      // An open crack is not the material's expansion: a cracked pair is left out of the
      // divergence, as out of the velocity gradient.
      if (!cracked) {
        if constexpr (Corrected) {
          // -div v_i = trace of the corrected gradient (L_i below): exact for a linear field.
          drhoi += volj * vij.dot(gI);
          if constexpr (Dim == 2)
            if (rz) MrrVolume -= volj * xij[0] * gI[0];
        } else {
          drhoi += volj * vij.dot(gradWi);
          if constexpr (Dim == 2)
            if (rz) MrrVolume -= volj * xij[0] * gradWi[0];
        }
      }
      if (balsara) {
        divi -= volj * vgrad;
        if constexpr (Dim == 2) curli[0] += volj * (vij[0] * gradW[1] - vij[1] * gradW[0]);
        if constexpr (Dim == 3) curli += volj * vij.cross(gradW);
      }
    }
    // Axisymmetric: the hoop force and rates (solvers/Axisymmetric.hpp).
    [[maybe_unused]] double Dtt = 0.0;
    if constexpr (Dim == 2)
      if (rz) {
        // The hoop force is the complement of the pair weights, pair by pair: where a pair
        // carries -max(p_i, 0) I of i's stress (across a contact or a crack), its share of the
        // hoop force carries the same. Else a ring whose pairs are all cracked, in tension,
        // has a hoop pull no radial stress balances and no hoop rate relaxes (its density is
        // frozen): it falls toward the axis, its p dV work drives e, and with it the tension,
        // down without bound (a steel ring among eroded tungsten reached -3e14 Pa).
        const double sigmaTT = (Solid ? Sdev[i](2, 2) : 0.0) - p[i];
        const rz::HoopForce hoop =
            rz::hoopForce(kr - krAcross, sigmaTT, -std::max(p[i], 0.0), krAcross,
                          product ? 1.0 / rhoi : 1.0 / (rhoi * rhoi), vi[0]);
        ai[0] += hoop.ar;
        dei += hoop.dedt;
        if constexpr (Solid)
          if (tensileI) { // (else R_i = 0)
            const double ar = -2.0 * Ri(0, 0) * krAS;
            ai[0] += ar;
            dei -= ar * vi[0];
          }
        const rz::HoopRates D = rz::hoopRates(vi[0], ringR_[i], MrrVolume, Solid ? Mrr : MrrVolume);
        drhoi -= D.volume;
        divi += D.volume;
        Dtt = D.strain;
      }
    if (surfaces) {
      // rz: the hoop force's share, -2 c k_r per unit sigma_tt (rz::hoopForce).
      if constexpr (Dim == 2)
        if (rz) Gi[0] -= 2.0 * (product ? 1.0 / rhoi : 1.0 / (rhoi * rhoi)) * kr;
      ai.noalias() += P[i] * Gi;
      area[i] = -mass[i] * Gi;
    }
    acc[i] = ai;
    dedt[i] = dei;
    if constexpr (Solid) {
      Lgrad[i].setZero();
      Lgrad[i].template topLeftCorner<Dim, Dim>() = Li;
      if constexpr (Dim == 2) Lgrad[i](2, 2) = Dtt; // the hoop rate in rz (0 in plane strain)
    }
    // Continuity, d rho_i/dt = -rho_i div v_i with div v_i = -sum_j (m_j/rho_j) v_ij . grad
    // W(r_ij, h_i): volume-weighted, so it stays accurate across a material interface with a
    // large density jump, and with i's own support (gather), so that it stays consistent where h
    // changes fast. (The pair-averaged gradient of the momentum equation over-compresses the Noh
    // shock by ~40% here; the gather form gives the post-shock density within 8%.)
    drhodt[i] = rhoi * drhoi;
    sumWH[i] = sumWHi;
    if constexpr (Aniso) {
      // The shape of the next H (solvers/IdealH.hpp): i's Voronoi cell among the row, in a box
      // as wide as i's longest reach, cut in the row's (rank-count-independent) order; every
      // shape_interval evaluations, staggered by id so that each step cuts the same share.
      // Half the cost of an ASPH step is the cell, and H moves only half way towards it a
      // step: a cell a few steps old is as good a target (decks/README, "ASPH").
      std::int32_t& age = cellAge[i]; // evaluations since the last cut, plus 1; 0: never cut
      if (age > 0 && age < shapeInterval) {
        ++age;
      } else {
        thread_local std::vector<Vec<Dim>> offsets;
        thread_local VoronoiCell<Dim> cell;
        offsets.clear();
        for (std::uint32_t j : row) offsets.push_back(x[j] - xi);
        cellMoment[i] = voronoiCell<Dim>(cell, offsets, K::support * hi) ? cell.moments().second
                                                                         : Tensor<Dim>::Zero();
        age = age == 0
                  ? 1 + static_cast<std::int32_t>(id[i] % static_cast<ParticleId>(shapeInterval))
                  : 1;
      }
    }
    muMax[i] = mui;
    if (balsara) {
      // Not into divv/curlv yet: later rows of this loop read them of their owned neighbors,
      // which must see the previous loop's values, as ghosts do (else the result depends on
      // the row order, and so on the rank count).
      divNew_[i] = divi;
      curlNew_[i] = curli.norm();
    }
  }
  if (balsara) {
    std::copy_n(divNew_.begin(), n, divv.begin());
    std::copy_n(curlNew_.begin(), n, curlv.begin());
  }
}

} // namespace spall::solvers::sph
