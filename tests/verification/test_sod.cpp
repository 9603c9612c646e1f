// Sod shock tube against the exact Riemann solution (decks/sod_1d.toml).
#include "ExactRiemann.hpp"
#include "RunDeck.hpp"

#include <gtest/gtest.h>

using namespace spall;
using namespace spall::verification;

namespace {

struct SodError {
  double l1Density, l1Velocity, l1Pressure;
  std::size_t particles;
};

SodError sodError(double resolution, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> overrides{"run.resolution=" + std::to_string(resolution)};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  int rc = -1;
  const auto dir =
      runSpall(deckPath("sod_1d.toml"), overrides, "sod_" + std::to_string(resolution), &rc);
  EXPECT_EQ(rc, 0);
  const auto s = io::readSnapshot(lastSnapshot(dir));
  EXPECT_NEAR(s.time, 0.2, 1e-12); // the run lands on its end time exactly
  const ExactRiemann exact({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4);
  const auto& x = s.fields.at("position");
  const auto& rho = s.fields.at("density");
  const auto& v = s.fields.at("velocity");
  const auto& p = s.fields.at("pressure");
  SodError e{0, 0, 0, 0};
  for (std::size_t i = 0; i < s.count; ++i) {
    // The walls at +-0.5 are out of the waves' reach; keep their boundary layers out too.
    if (std::abs(x[i]) > 0.4) continue;
    const auto ex = exact.sample(x[i] / s.time);
    e.l1Density += std::abs(rho[i] - ex.rho);
    e.l1Velocity += std::abs(v[i] - ex.u);
    e.l1Pressure += std::abs(p[i] - ex.p);
    ++e.particles;
  }
  e.l1Density /= static_cast<double>(e.particles);
  e.l1Velocity /= static_cast<double>(e.particles);
  e.l1Pressure /= static_cast<double>(e.particles);
  return e;
}

} // namespace

TEST(ExactRiemann, ToroTest1StarState) {
  // Toro (2009), Table 4.2, test 1 (Sod): p* = 0.30313, u* = 0.92745 (5 digits published).
  const ExactRiemann r({1.0, 0.0, 1.0}, {0.125, 0.0, 0.1}, 1.4);
  EXPECT_NEAR(r.pStar, 0.30313, 5e-6);
  EXPECT_NEAR(r.uStar, 0.92745, 5e-6);
  // Post-shock density 0.26557 and the contact's left density 0.42632 (Toro, Table 4.3).
  EXPECT_NEAR(r.sample(1.0).rho, 0.26557, 5e-5);
  EXPECT_NEAR(r.sample(0.5).rho, 0.42632, 5e-5);
}

TEST(Sod, L1DensityErrorIsSmallAndFallsWithResolution) {
  const SodError coarse = sodError(1.0);
  const SodError fine = sodError(2.0);
  const double order = std::log(coarse.l1Density / fine.l1Density) / std::log(2.0);
  std::printf("Sod L1(rho): %.4e (%zu particles) -> %.4e (%zu particles), observed order %.2f\n",
              coarse.l1Density, coarse.particles, fine.l1Density, fine.particles, order);
  std::printf("Sod L1(u): %.4e -> %.4e; L1(p): %.4e -> %.4e\n", coarse.l1Velocity, fine.l1Velocity,
              coarse.l1Pressure, fine.l1Pressure);
  // Bound: SPH with Monaghan-Gingold viscosity smears the shock over ~3h and the contact over
  // ~2h of the coarse right state; with 450 particles that is an L1 density error of several
  // 1e-3 (measured 5.5e-3 at n_h = 2). 8e-3 leaves room for round-off-level changes of the
  // scheme but fails a wrong wave speed (1% in c already gives ~1e-2) or a missing wall.
  EXPECT_LT(coarse.l1Density, 8e-3);
  // Shock-dominated problems converge at first order at best in L1 (measured 0.9); require a
  // clear decrease (order > 0.5) so that a resolution-independent error cannot pass.
  EXPECT_GT(order, 0.5);
}
