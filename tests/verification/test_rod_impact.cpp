// Lam, Shen & Gong (2001) rod impact cases 1-3 against water-hammer theory (their Eqs. 30-32).
#include "RunDeck.hpp"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>

using namespace spall;
using namespace spall::verification;

namespace {

constexpr double rho0 = 8930.0, c0 = 3940.0, v0 = 20.0;

// The plateau of a compressive stress history: the median over the middle 60% of the interval
// where the stress is beyond half the expected value (leaves out the smeared rise and fall).
double plateau(const ProbeSeries& s, double expected) {
  std::vector<double> inside;
  for (std::size_t k = 0; k < s.t.size(); ++k)
    if (s.value[k] < 0.5 * expected) inside.push_back(s.value[k]);
  if (inside.size() < 5) return 0.0;
  const std::size_t a = inside.size() / 5, b = inside.size() - inside.size() / 5;
  std::vector<double> mid(inside.begin() + static_cast<std::ptrdiff_t>(a),
                          inside.begin() + static_cast<std::ptrdiff_t>(b));
  std::nth_element(mid.begin(), mid.begin() + static_cast<std::ptrdiff_t>(mid.size() / 2),
                   mid.end());
  return mid[mid.size() / 2];
}

// Case 1 (copper on copper) run with `sets`, its checks with the same bounds for every method;
// the run's directory (empty if it failed).
void checkCase1(const std::vector<std::string>& sets, const std::string& name,
                std::filesystem::path* out = nullptr) {
  int rc = -1;
  const auto dir = runSpall(deckPath("rod_impact_copper.toml"), sets, name, &rc);
  ASSERT_EQ(rc, 0);
  if (out) *out = dir;
  // Eq. 31-32: sigma_c = -rho c v / 2 = -351.8 MPa. 5%: the tolerance; the Mie-Gruneisen
  // stiffening at eta ~ 0.25% shifts the plateau by ~0.4% and SPH ringing by ~1%.
  const double sigmaC = -rho0 * c0 * v0 / 2.0;
  const auto probes = readProbes(dir);
  const double measured = plateau(probes.at("striker_mid").at("stress_xx"), sigmaC);
  std::printf("case 1 plateau: %.2f MPa (theory %.2f MPa)\n", measured / 1e6, sigmaC / 1e6);
  EXPECT_NEAR(measured / sigmaC, 1.0, 0.05);

  // Fig. 1 at 7.7 us: the pulse in the target is twice the striker long (20 mm). Measured as
  // the extent of target particles compressed beyond half the plateau; the fronts are smeared
  // over ~2h = 0.15 mm each, so 5% (1 mm) is a fair tolerance.
  const auto s77 = io::readSnapshot(snapshotAt(dir, 7.7e-6));
  double lo = 1e9, hi = -1e9;
  for (std::size_t i = 0; i < s77.count; ++i) {
    const double x = s77.fields.at("position")[i];
    const double sxx = s77.fields.at("stress")[i];
    if (s77.fields.at("body")[i] == 1 && sxx < 0.5 * sigmaC)
      lo = std::min(lo, x), hi = std::max(hi, x);
  }
  std::printf("case 1 pulse length at %.2f us: %.2f mm (theory 20 mm)\n", s77.time * 1e6,
              (hi - lo) * 1e3);
  EXPECT_NEAR((hi - lo) / 0.020, 1.0, 0.05);

  // Fig. 2 at 12.8 us: the striker is at rest, the rear 10 mm of the target moves at 20 m/s.
  const auto s = io::readSnapshot(lastSnapshot(dir));
  double strikerMomentum = 0, strikerMass = 0, rearMomentum = 0, rearMass = 0;
  for (std::size_t i = 0; i < s.count; ++i) {
    const double x = s.fields.at("position")[i], v = s.fields.at("velocity")[i],
                 m = s.fields.at("mass")[i];
    if (s.fields.at("body")[i] == 0) strikerMomentum += m * v, strikerMass += m;
    // The rear 10 mm, less the smeared edge of the reflected front (~1 mm).
    else if (x > 0.031)
      rearMomentum += m * v, rearMass += m;
  }
  const double vStriker = strikerMomentum / strikerMass, vRear = rearMomentum / rearMass;
  std::printf("case 1 at 12.8 us: striker %.3f m/s (theory 0), target rear %.3f m/s (theory 20)\n",
              vStriker, vRear);
  // 5% of the impact speed: the SPH tails of the fronts carry a few percent of the momentum.
  EXPECT_NEAR(vStriker, 0.0, 0.05 * v0);
  EXPECT_NEAR(vRear, v0, 0.05 * v0);

  // Conservation (no wall acts): mass exact, momentum to round-off, energy drift bounded.
  const auto h = readHistory(dir);
  const double p0 = h.at("momentum_x").front(), m0 = h.at("mass").front(),
               e0 = h.at("total_energy").front();
  double dp = 0, de = 0;
  for (std::size_t k = 0; k < h.at("step").size(); ++k) {
    ASSERT_EQ(h.at("mass")[k], m0) << "mass changed at row " << k;
    dp = std::max(dp, std::abs(h.at("momentum_x")[k] - p0) / std::abs(p0));
    de = std::max(de, std::abs(h.at("total_energy")[k] - e0) / e0);
  }
  std::printf("case 1 conservation: momentum %.2e, total energy %.2e (relative, worst row)\n", dp,
              de);
  // Pairwise antisymmetric forces: momentum changes only by round-off, ~1e-16 per step.
  EXPECT_LT(dp, 1e-12);
  // Kick-drift-kick is second order; the energy error of ~2700 steps stays well below 0.5%
  // (MPM: FLIP-MUSL to truncation error, measured 1e-3 at worst).
  EXPECT_LT(de, 5e-3);
}

} // namespace

TEST(RodImpact, Case1CopperOnCopperMatchesWaterHammer) {
  checkCase1({}, "rod_case1");
}

// The same case with the material point method (GIMP, FLIP): the bounds, the contact
// stress within 5% and the pulse twice the striker long. No viscosity: the fronts overshoot by
// ~30% (Gibbs), which the plateau's median leaves out.
TEST(RodImpact, Case1WithMpmMatchesWaterHammer) {
  checkCase1({"solver.method=mpm"}, "rod_case1_mpm");
}

namespace {

// Case 1 with MPM and `sets`: the bounds of checkCase1, then the striker probe's largest
// compression within `overshoot` of the plateau and the plateau within 1% of -rho c v / 2 (the
// EOS's stiffening is 0.4%).
void checkFront(std::vector<std::string> sets, const std::string& name, double overshoot) {
  sets.insert(sets.begin(), "solver.method=mpm");
  std::filesystem::path dir;
  checkCase1(sets, name, &dir);
  ASSERT_FALSE(dir.empty());
  const double sigmaC = -rho0 * c0 * v0 / 2.0;
  const auto& s = readProbes(dir).at("striker_mid").at("stress_xx");
  const double plateauStress = plateau(s, sigmaC);
  const double peak = *std::min_element(s.value.begin(), s.value.end());
  std::printf("%s: peak %.1f MPa, plateau %.1f MPa (overshoot %.1f%%)\n", name.c_str(), peak / 1e6,
              plateauStress / 1e6, 100.0 * (peak / plateauStress - 1.0));
  EXPECT_LT(peak / plateauStress - 1.0, overshoot);
  EXPECT_NEAR(plateauStress / sigmaC, 1.0, 0.01);
}

} // namespace

// ... with MPM's bulk viscosity at Uintah's coefficients (linear 0.2, quadratic 2): the same
// bounds, and the front no longer rings: the peak within 12% of the plateau (measured 7.2%;
// without the viscosity 32.6%, at LS-DYNA's 0.06 / 1.5 21%), the plateau within 1% (0.1%).
TEST(RodImpact, Case1WithMpmAndBulkViscosityDoesNotRing) {
  checkFront({"solver.mpm.viscosity={linear=0.2, quadratic=2.0}"}, "rod_case1_mpm_q", 0.12);
}

// ... and with APIC as well: FLIP carries the front's ringing on the points from step to step
// (the velocity modes the grid cannot hold); APIC's points take the grid's velocity and its
// gradient, so with the same viscosity the peak is within 3% of the plateau (measured 0.8%;
// APIC without the viscosity 21.5%, FLIP's 7.2% above).
TEST(RodImpact, Case1WithMpmApicAndBulkViscosityDoesNotOvershoot) {
  checkFront({"solver.mpm.transfer=\"apic\"", "solver.mpm.viscosity={linear=0.2, quadratic=2.0}"},
             "rod_case1_mpm_apic_q", 0.03);
}

TEST(RodImpact, Case2RigidWallDoublesTheStress) {
  int rc = -1;
  const auto dir = runSpall(deckPath("rod_impact_rigid_wall.toml"), {}, "rod_case2", &rc);
  ASSERT_EQ(rc, 0);
  // Eq. 30 against a wall at rest: sigma = -rho c v = -703.6 MPa; 5% as in case 1.
  const double sigma = -rho0 * c0 * v0;
  const double measured = plateau(readProbes(dir).at("striker_mid").at("stress_xx"), sigma);
  std::printf("case 2 plateau: %.2f MPa (theory %.2f MPa)\n", measured / 1e6, sigma / 1e6);
  EXPECT_NEAR(measured / sigma, 1.0, 0.05);
}

TEST(RodImpact, Case3ThickerPmmaPadLowersThePeakStress) {
  // Lam et al. Fig. 6: pads of L_p = 5, 10, 20 mm on the 10 mm copper striker.
  std::vector<double> peaks;
  for (double lp : {0.005, 0.010, 0.020}) {
    const std::string pad = std::to_string(-lp), sMin = std::to_string(-lp - 0.010);
    const std::string mid = std::to_string(-lp - 0.005);
    int rc = -1;
    const auto dir =
        runSpall(deckPath("rod_impact_pmma_pad.toml"),
                 {"body.pad.shape.min=[" + pad + "]", "body.striker.shape.min=[" + sMin + "]",
                  "body.striker.shape.max=[" + pad + "]",
                  "probe.striker_mid.position=[" + mid + "]", "output.every=1e-5"},
                 "rod_case3_" + std::to_string(lp), &rc);
    ASSERT_EQ(rc, 0);
    const auto probes = readProbes(dir);
    const auto& s = probes.at("striker_mid").at("stress_xx");
    peaks.push_back(-*std::min_element(s.value.begin(), s.value.end()));
    std::printf("case 3, pad %.0f mm: peak striker stress %.1f MPa\n", lp * 1e3,
                peaks.back() / 1e6);
  }
  // Their Fig. 6: the peak falls fast while L_p <= L_s and hardly beyond. Measured: 161, 106,
  // 106 MPa. A drop of more than 10% from 5 to 10 mm, and within 10% from 10 to 20 mm.
  EXPECT_GT(peaks[0], 1.1 * peaks[1]);
  EXPECT_NEAR(peaks[2] / peaks[1], 1.0, 0.10);
  // "the maximum stress is reduced by 74%" for L_p = 2 L_s against the bare striker's 351.8 MPa
  // (read off their figures; we allow 74% +- 10 points for that reading and the SPH smearing).
  const double reduction = 1.0 - peaks[2] / (rho0 * c0 * v0 / 2.0);
  std::printf("case 3, pad 20 mm: peak reduced by %.0f%% (Lam et al.: 74%%)\n", 100 * reduction);
  EXPECT_NEAR(reduction, 0.74, 0.10);
}

// decks/rod_impact_copper_strength.toml: case 1 with von Mises strength (G = 47.7 GPa,
// Y0 = 0.76 GPa). 1D is uniaxial strain, so waves run at c_L = sqrt(C0^2 + 4G/(3 rho0)).
TEST(RodImpactStrength, ElasticImpactRunsAtTheLongitudinalSpeed) {
  int rc = -1;
  const auto dir = runSpall(deckPath("rod_impact_copper_strength.toml"), {"run.end_time=6e-6"},
                            "rod_strength_elastic", &rc);
  ASSERT_EQ(rc, 0);
  const double G = 47.7e9;
  const double cL = std::sqrt(c0 * c0 + 4.0 * G / (3.0 * rho0));
  // -rho0 c_L v / 2 = -424.9 MPa, below the HEL: elastic. 1%: the Mie-Gruneisen stiffening at
  // eta ~ 0.2% shifts it by ~0.3% (measured with G = 45 GPa: -422.28 vs -421.16 MPa), ringing
  // is below 0.1% on the striker's plateau.
  const double sigmaC = -rho0 * cL * v0 / 2.0;
  const double measured = plateau(readProbes(dir).at("striker_mid").at("stress_xx"), sigmaC);
  std::printf("case 1 with strength: plateau %.2f MPa (theory %.2f MPa; EOS only %.2f MPa)\n",
              measured / 1e6, sigmaC / 1e6, -rho0 * c0 * v0 / 2e6);
  EXPECT_NEAR(measured / sigmaC, 1.0, 0.01);
  // Elastic: no particle has yielded.
  const auto s = io::readSnapshot(lastSnapshot(dir));
  double epsMax = 0.0;
  for (double e : s.fields.at("plastic_strain")) epsMax = std::max(epsMax, e);
  EXPECT_EQ(epsMax, 0.0);
}

TEST(RodImpactStrength, FastImpactSendsAnElasticPrecursorAtTheHel) {
  int rc = -1;
  const double t = 7.5e-6;
  const auto dir =
      runSpall(deckPath("rod_impact_copper_strength.toml"),
               {"run.end_time=7.5e-6", "body.striker.velocity=[200.0]"}, "rod_strength_hel", &rc);
  ASSERT_EQ(rc, 0);
  const double G = 47.7e9, Y = 0.76e9, S = 1.49;
  const double cL = std::sqrt(c0 * c0 + 4.0 * G / (3.0 * rho0));
  // Hugoniot elastic limit in uniaxial strain: yield at eps_y = Y/(2G); the EOS's pressure there
  // (a0 eta + b0 eta^2, eta = 1/(1 - eps_y) - 1, b0 = a0 (2S - 1)) plus S_xx = 2Y/3: 1.637 GPa
  // (the linear estimate (K + 4G/3) Y/(2G) gives 1.611 GPa).
  const double a0 = rho0 * c0 * c0, epsY = Y / (2.0 * G), eta = 1.0 / (1.0 - epsY) - 1.0;
  const double hel = a0 * eta + a0 * (2.0 * S - 1.0) * eta * eta + 2.0 * Y / 3.0;
  // The precursor runs at c_L ahead of the plastic wave (~C0 + S u_p): at 7.5 us its front is at
  // c_L t = 35.7 mm and the plastic front ~5 mm behind it. The precursor's plateau is the median
  // stress 1.5-3.5 mm behind the elastic front; 3%: the fronts are smeared over ~0.5 mm and the
  // plateau rings by ~2% (measured 1.64-1.69 GPa at 5 us, where it is shorter).
  const auto snap = io::readSnapshot(lastSnapshot(dir));
  const double front = cL * t;
  std::vector<double> band;
  double epsMax = 0.0;
  for (std::size_t i = 0; i < snap.count; ++i) {
    const double x = snap.fields.at("position")[i];
    if (x > front - 3.5e-3 && x < front - 1.5e-3) band.push_back(-snap.fields.at("stress")[i]);
    epsMax = std::max(epsMax, snap.fields.at("plastic_strain")[i]);
  }
  ASSERT_GT(band.size(), 20u);
  std::nth_element(band.begin(), band.begin() + static_cast<std::ptrdiff_t>(band.size() / 2),
                   band.end());
  const double precursor = band[band.size() / 2];
  std::printf("200 m/s: elastic precursor %.3f GPa (HEL %.3f GPa), max plastic strain %.4f\n",
              precursor / 1e9, hel / 1e9, epsMax);
  EXPECT_NEAR(precursor / hel, 1.0, 0.03);
  EXPECT_GT(epsMax, 0.0); // behind it the material has yielded
}

TEST(RodImpactStrength, RigidWallDoublesTheElasticStress) {
  int rc = -1;
  const auto dir =
      runSpall(deckPath("rod_impact_rigid_wall_strength.toml"), {}, "rod_strength_wall", &rc);
  ASSERT_EQ(rc, 0);
  const double cL = std::sqrt(c0 * c0 + 4.0 * 47.7e9 / (3.0 * rho0));
  // -rho0 c_L v = -849.9 MPa, elastic (below the 1.64 GPa HEL). 1% as for case 1 with strength;
  // measured -854.4 MPa (+0.5%: the Mie-Gruneisen stiffening at twice the strain).
  const double sigma = -rho0 * cL * v0;
  const double measured = plateau(readProbes(dir).at("striker_mid").at("stress_xx"), sigma);
  std::printf("case 2 with strength: plateau %.2f MPa (theory %.2f MPa)\n", measured / 1e6,
              sigma / 1e6);
  EXPECT_NEAR(measured / sigma, 1.0, 0.01);
}

// MPM with the target `fixed` (a rigid anvil: its grid nodes move at its velocity, 0) and
// frictionless contact: Lam's case 2 without a wall. Eq. 30: sigma = -rho c v = -703.6 MPa in
// the striker (5%, as case 1; measured 0.4%), the anvil never moves (exactly), and after 2L/c the
// striker flies back at the impact speed (within 5%: measured -19.6 m/s, the FLIP fronts' ringing
// keeps 2% of the energy in the striker). With one velocity field (welded) the anvil's nodes
// would hold the striker's face in tension instead: it leaves at -2 m/s (the contrast).
// The anvil's support impulse (the momentum its held nodes hand the striker) is booked as an
// external impulse on the anvil's points: momentum against the books within 1e-12 (measured
// 5e-16; unbooked, the error was the striker's reversal, 2.0 of its momentum). Energy within
// 5e-3 (measured 3.4e-4; 1.2e-2 while a node one cell inside the striker was held for an anvil
// point on the edge of its support, MpmGridImpl.hpp's kHolds).
TEST(RodImpact, Case2WithMpmOnAFixedAnvil) {
  int rc = -1;
  const auto dir =
      runSpall(deckPath("rod_impact_copper.toml"),
               {"solver.method=mpm", "solver.contact=frictionless", "body.target.fixed=true"},
               "rod_case2_mpm_anvil", &rc);
  ASSERT_EQ(rc, 0);
  const double sigma = -rho0 * c0 * v0;
  const double measured = plateau(readProbes(dir).at("striker_mid").at("stress_xx"), sigma);
  std::printf("anvil plateau: %.2f MPa (theory %.2f MPa)\n", measured / 1e6, sigma / 1e6);
  EXPECT_NEAR(measured / sigma, 1.0, 0.05);
  const auto s0 = io::readSnapshot(snapshotAt(dir, 0.0));
  const auto s = io::readSnapshot(lastSnapshot(dir));
  double p = 0, m = 0, x0 = 0, x1 = 0;
  for (std::size_t i = 0; i < s.count; ++i) {
    if (s.fields.at("body")[i] == 0)
      p += s.fields.at("mass")[i] * s.fields.at("velocity")[i], m += s.fields.at("mass")[i];
    else
      x1 += s.fields.at("position")[i];
  }
  for (std::size_t i = 0; i < s0.count; ++i)
    if (s0.fields.at("body")[i] == 1) x0 += s0.fields.at("position")[i];
  std::printf("anvil: striker leaves at %.3f m/s (theory -20)\n", p / m);
  EXPECT_NEAR(p / m, -v0, 0.05 * v0);
  EXPECT_EQ(x1, x0); // the anvil's points never move: their sum is the same to the bit
  const double momentum = summaryNumber(dir, "momentum_relative");
  EXPECT_GE(momentum, 0.0) << "no momentum_relative in summary.json";
  EXPECT_LT(momentum, 1e-12);
  const double energy = summaryNumber(dir, "energy_relative");
  EXPECT_GE(energy, 0.0) << "no energy_relative in summary.json";
  EXPECT_LT(energy, 5e-3);
}
