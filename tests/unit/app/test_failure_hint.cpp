// The hint that ends a failed run's message (app/FailureHint.hpp): each failure's signature gets
// its own advice, and only its own.
#include "spall/app/FailureHint.hpp"

#include <gtest/gtest.h>

#include <limits>

using namespace spall::app;

namespace {

// A 2D SPH particle that went non-finite with a normal neighborhood, density and h.
FailureSigns plain() {
  FailureSigns s;
  s.nonFinite = true;
  s.dimension = 2;
  s.neighbors = 26;
  s.pMin = 1e9;
  s.collapseFraction = 1e-10;
  s.endTime = 1e-5;
  return s;
}

bool says(const std::string& hint, const std::string& what) {
  return hint.find(what) != std::string::npos;
}

} // namespace

TEST(FailureHint, NonFiniteWithNothingElseAsksForASmallerCfl) {
  const std::string h = failureHint(plain());
  EXPECT_TRUE(says(h, "smaller solver.cfl")) << h;
  EXPECT_FALSE(says(h, "ASPH")) << h;
}

// The stability matrix's fine ASPH hydro cells at 6-10 km/s: a plate or projectile particle
// in -2 to -13 GPa of tension goes non-finite; a smaller cfl fails more cells, SPH finishes them.
TEST(FailureHint, AsphInTensionPointsToSphNotToTheCfl) {
  FailureSigns s = plain();
  s.asph = true;
  s.pMin = -1.35e10;
  const std::string h = failureHint(s);
  EXPECT_TRUE(says(h, "solver.method = \"sph\"")) << h;
  EXPECT_TRUE(says(h, "-1.35e+10 Pa")) << h;
  EXPECT_TRUE(says(h, "does not help")) << h;
  // The same particle under compression only, or with SPH: the usual advice.
  s.pMin = 2e9;
  EXPECT_TRUE(says(failureHint(s), "try a smaller solver.cfl"));
  s.pMin = -1.35e10;
  s.asph = false;
  EXPECT_TRUE(says(failureHint(s), "try a smaller solver.cfl"));
  // No good step sampled (no rescue copy): the pressure is unknown, +inf.
  s.asph = true;
  s.pMin = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(says(failureHint(s), "try a smaller solver.cfl"));
}

TEST(FailureHint, EarlierSignaturesComeFirst) {
  FailureSigns s = plain();
  s.asph = true;
  s.pMin = -1e9;
  s.compression = 12.0; // interpenetration beats the tension
  EXPECT_TRUE(says(failureHint(s), "compressed beyond any shock state"));
  s.compression = 1.0;
  s.neighbors = 5; // fewer than 3 x Dim
  EXPECT_TRUE(says(failureHint(s), "few neighbors"));
  s = plain();
  s.mpm = true;
  s.frictionless = true;
  EXPECT_TRUE(says(failureHint(s), "MPM and a velocity field per body"));
  s.nonFinite = false;
  s.frictionless = false;
  EXPECT_TRUE(says(failureHint(s), "1e-10 of run.end_time (1.000e-15 s) counts as collapsed"));
}

// A run stopped for creating energy (output.max_energy_error): its own advice, not the collapse's
// floor; the ASPH-in-tension signature still wins (the 6 km/s al_al cell that crawled stops with
// an ASPH projectile particle that was at -1.8e10 Pa).
TEST(FailureHint, CreatedEnergyNamesTheBoundAndKeepsTheAsphSignature) {
  FailureSigns s = plain();
  s.nonFinite = false;
  s.energy = true;
  const std::string h = failureHint(s);
  EXPECT_TRUE(says(h, "creates energy")) << h;
  EXPECT_TRUE(says(h, "output.max_energy_error = 0")) << h;
  EXPECT_FALSE(says(h, "counts as collapsed")) << h;
  s.asph = true;
  s.pMin = -1.8e10;
  EXPECT_TRUE(says(failureHint(s), "solver.method = \"sph\"")) << failureHint(s);
  s.compression = 12.0;
  EXPECT_TRUE(says(failureHint(s), "compressed beyond any shock state"));
}
