// The oscillating clamped plate of Gray, Monaghan & Swift (2001): the period of its first bending
// mode against Euler-Bernoulli plate theory, T = 2 pi / omega with omega^2 = E H^2 k^4 /
// (12 rho (1 - nu^2)), k = 1.8751/L (decks/elastic_plate_2d.toml).
#include "RunDeck.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <gtest/gtest.h>
#include <iterator>
#include <numbers>

using namespace spall;
using namespace spall::verification;

namespace {

double analyticPeriod() {
  const double E = 2.0e6, nu = 0.3975, rho = 1000.0, H = 0.02, L = 0.2;
  const double k = 1.8751040687 / L;
  const double omega = std::sqrt(E * H * H * std::pow(k, 4) / (12.0 * rho * (1.0 - nu * nu)));
  return 2.0 * std::numbers::pi / omega;
}

struct PlateRun {
  double period = 0.0;    // four times the first zero crossing of the tip's v_y
  double amplitude = 0.0; // largest tip deflection
  double drift = 0.0;     // largest relative change of the total energy
  double momentum = -1.0; // summary.json's momentum error against the books (the clamp's impulse)
};

// Runs the deck at `resolution` until the tip's v_y first changes sign (a quarter period).
PlateRun run(double resolution, double endTime, const std::string& tag) {
  int rc = -1;
  const auto dir = runSpall(deckPath("elastic_plate_2d.toml"),
                            {"run.resolution=" + std::to_string(resolution),
                             "run.end_time=" + std::to_string(endTime), "output.every=0.05"},
                            tag, &rc);
  EXPECT_EQ(rc, 0);
  PlateRun out;
  const auto probes = readProbes(dir);
  const auto& v = probes.at("tip").at("velocity_y");
  const auto& y = probes.at("tip").at("position_y");
  EXPECT_GT(v.value.front(), 0.5); // moving up in the first mode, tip speed 0.5703 m/s
  for (std::size_t k = 1; k < v.t.size() && out.period == 0.0; ++k)
    if (v.value[k - 1] > 0.0 && v.value[k] <= 0.0) {
      const double t =
          v.t[k - 1] + (v.t[k] - v.t[k - 1]) * v.value[k - 1] / (v.value[k - 1] - v.value[k]);
      out.period = 4.0 * t;
    }
  for (double yi : y.value) out.amplitude = std::max(out.amplitude, yi - y.value.front());
  const auto h = readHistory(dir);
  const double e0 = h.at("total_energy").front();
  for (double e : h.at("total_energy")) out.drift = std::max(out.drift, std::abs(e - e0) / e0);
  out.momentum = summaryNumber(dir, "momentum_relative");
  std::filesystem::remove_all(dir);
  EXPECT_GT(out.period, 0.0) << "the tip never turned back by t = " << endTime;
  return out;
}

} // namespace

// Spacings 4 mm and 2 mm (5 and 10 particles through the thickness): the error shrinks at second
// order, and the Richardson extrapolation of the two is the analytic period. Measured: +36.8% and
// +9.7% (ratio 3.8), extrapolated +0.6% (with the artificial stress, which the deck turns off:
// +43.4% and +13.7%, ratio 3.2, extrapolated +3.8%).
TEST(ElasticPlate, PeriodConvergesToPlateTheory) {
  const double T = analyticPeriod();
  EXPECT_NEAR(T, 0.2540, 1e-4); // the value the deck's header states
  const PlateRun coarse = run(0.25, 0.1, "plate4"), fine = run(0.5, 0.08, "plate2");
  const double eCoarse = coarse.period / T - 1.0, eFine = fine.period / T - 1.0;
  const double extrapolated = fine.period + (fine.period - coarse.period) / 3.0;
  std::printf("[ measured ] T = %.4f s (%+.1f%%) at 4 mm, %.4f s (%+.1f%%) at 2 mm, Richardson "
              "%.4f s (%+.1f%%); analytic %.4f s; energy drift %.1e\n",
              coarse.period, 100 * eCoarse, fine.period, 100 * eFine, extrapolated,
              100 * (extrapolated / T - 1.0), T, fine.drift);
  // Too soft on a coarse lattice (the outer fibres carry the bending), less so when refined.
  EXPECT_GT(eCoarse, eFine);
  EXPECT_GT(eFine, 0.0);
  // Second order: halving the spacing divides the error by 4 (measured 3.8); 3 still rejects
  // first order (2), which is what the plain, uncorrected gradient shows.
  EXPECT_GT(eCoarse / eFine, 3.0);
  // The second-order extrapolation within 2% (the issue asked 5%): what remains is the clamp's
  // root rotation and higher-order terms (+0.6%); the artificial stress's bias (+3.8%), which
  // went unnoticed under 5%, fails it.
  EXPECT_NEAR(extrapolated / T, 1.0, 0.02);
  // The clamp does no work and every pair term conserves energy: what is left is the time
  // integration's error (measured 1.6e-6); 1e-4 would catch a non-conservative term.
  EXPECT_LT(fine.drift, 1e-4);
  // The clamp's reaction (the support's force on the fixed particles, -m a) is booked as an
  // external impulse: momentum then balances to round-off (measured 1.2e-16 over 2000 steps at
  // 2 mm). Unbooked, the error is the plate's own momentum, of the order of its scale.
  EXPECT_GE(fine.momentum, 0.0) << "no momentum_relative in summary.json";
  EXPECT_LT(fine.momentum, 1e-12);
}

// The deck as shipped (1 mm, 20 particles through the thickness): period within 5% of plate
// theory directly, and the tip amplitude V c0 / omega = 2.306 cm within 5%. Measured: +0.98%,
// 2.345 cm (+1.7%), energy drift 3.5e-6 (with the artificial stress: +5.9%). About 2 minutes
// on one rank.
TEST(ElasticPlateLong, PeriodWithinFivePercentAtOneMillimetre) {
  const double T = analyticPeriod();
  const PlateRun r = run(1.0, 0.075, "plate1");
  std::printf("[ measured ] T = %.4f s (%+.2f%% of %.4f s), tip amplitude %.4f m, energy drift "
              "%.1e\n",
              r.period, 100 * (r.period / T - 1.0), T, r.amplitude, r.drift);
  EXPECT_NEAR(r.period / T, 1.0, 0.05);
  const double amplitude = 0.5703 / (2.0 * std::numbers::pi / T);
  EXPECT_NEAR(r.amplitude / amplitude, 1.0, 0.05);
  EXPECT_LT(r.drift, 1e-4);
}
