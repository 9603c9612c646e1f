// Rigid-wall images are made and refreshed from the field flags alone: positions mirrored
// across the plane, kReflectVector fields reflected (P v), kReflectTensor fields mirrored
// (P T P), everything else copied; in a corner the image of an image carries both reflections.
#include "spall/solvers/Boundaries.hpp"

#include "SolverLattice.hpp"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <limits>

using namespace spall;

namespace {

BoundaryConfig wall(std::vector<double> point, std::vector<double> normal) {
  BoundaryConfig b;
  b.type = BoundaryType::RigidWall;
  b.point = std::move(point);
  b.normal = std::move(normal);
  return b;
}

Tensor<3> symmetric3(double xx, double yy, double xy) {
  Tensor<3> S = Tensor<3>::Zero();
  S(0, 0) = xx, S(1, 1) = yy, S(0, 1) = S(1, 0) = xy, S(2, 2) = -xx - yy;
  return S;
}

} // namespace

TEST(Boundaries, WallImagesFollowTheFieldFlagsAndRefreshInCreationOrder) {
  ParticleStore s;
  ParticleFields<2> f;
  fixtures::registerFields(s, f, {.strength = true, .corrected = true, .asph = true});
  s.resizeLocal(1);
  s[f.x][0] = Vec<2>(0.1, 0.2); // near both walls of the corner x = 0, y = 0
  s[f.v][0] = Vec<2>(-3.0, -4.0);
  s[f.rho][0] = 7.0;
  s[f.S][0] = symmetric3(1.0, 2.0, 5.0);
  Tensor<2> H;
  H << 2.0, 0.5, 0.5, 3.0;
  s[f.H][0] = H;
  solvers::Boundaries<2> b({wall({0.0, 0.0}, {1.0, 0.0}), wall({0.0, 0.0}, {0.0, 1.0})}, s, f);
  b.buildGhosts(s, 1.0);
  // Images in creation order: across x = 0 (of the particle), across y = 0 (of the particle and
  // of the first image).
  ASSERT_EQ(s.ghostCount(), 3u);
  const auto x = s[f.x];
  const auto v = s[f.v];
  EXPECT_EQ(x[1], Vec<2>(-0.1, 0.2));
  EXPECT_EQ(v[1], Vec<2>(3.0, -4.0));
  EXPECT_EQ(x[2], Vec<2>(0.1, -0.2));
  EXPECT_EQ(v[2], Vec<2>(-3.0, 4.0));
  EXPECT_EQ(x[3], Vec<2>(-0.1, -0.2));
  EXPECT_EQ(v[3], Vec<2>(3.0, 4.0));
  // A mirror flips the off-diagonal of a symmetric tensor; two mirrors restore it.
  EXPECT_EQ(s[f.S][1](0, 1), -5.0);
  EXPECT_EQ(s[f.S][1](0, 0), 1.0);
  EXPECT_EQ(s[f.S][3](0, 1), 5.0);
  EXPECT_EQ(s[f.H][1](0, 1), -0.5);
  EXPECT_EQ(s[f.H][2](0, 1), -0.5);
  EXPECT_EQ(s[f.H][3](0, 1), 0.5);
  for (std::size_t g = 1; g <= 3; ++g) EXPECT_EQ(s[f.rho][g], 7.0);

  // The source changes (a density pass, a new kernel correction): a refresh of those columns
  // copies them again, mirrored where flagged, an image of an image from its refreshed source.
  s[f.rho][0] = 9.0;
  s[f.B][0] = symmetric3(1.5, 0.5, 0.25);
  const std::vector<std::size_t> refresh = s.columnsWith(kRefresh);
  b.refreshGhosts(s, refresh);
  const std::size_t correction[] = {f.B.index};
  b.refreshGhosts(s, correction);
  for (std::size_t g = 1; g <= 3; ++g) EXPECT_EQ(s[f.rho][g], 9.0);
  EXPECT_EQ(s[f.B][1](0, 1), -0.25);
  EXPECT_EQ(s[f.B][2](0, 1), -0.25);
  EXPECT_EQ(s[f.B][3](0, 1), 0.25);
  EXPECT_EQ(s[f.B][3](0, 0), 1.5);
}

TEST(ParticleFields, FlagsSayWhatGhostsReceive) {
  ParticleStore s;
  ParticleFields<3> f;
  fixtures::registerFields(s, f, {.balsara = true, .strength = true});
  const auto names = [&](unsigned flags) {
    std::vector<std::string> out;
    for (std::size_t c : s.columnsWith(flags)) out.push_back(s.columns()[c]->info().name);
    return out;
  };
  // What the neighbor search and the force loop read of a neighbor, and nothing else.
  EXPECT_EQ(names(kHalo), (std::vector<std::string>{"id", "position", "velocity", "mass", "density",
                                                    "pressure", "sound_speed", "material",
                                                    "smoothing_length", "velocity_divergence",
                                                    "velocity_curl", "deviatoric_stress"}));
  EXPECT_EQ(names(kRefresh), (std::vector<std::string>{"density", "pressure", "sound_speed"}));
  // A module that needs another field on ghosts adds the flag (frictionless contact: the body).
  s.addFlags(f.body.index, kHalo);
  const auto halo = names(kHalo);
  EXPECT_EQ(halo.size(), 13u);
  EXPECT_NE(std::find(halo.begin(), halo.end(), "body"), halo.end());
  EXPECT_EQ(names(kHalo | kRefresh).size(), 3u);
}

// A rigid wall's normal constraint (Boundaries::holdAcceleration, holdVelocity): within kHold h of
// the plane a particle keeps its motion along the wall and its motion away from it; its approach
// stops, the kinetic energy of the approach becoming heat; one that stepped across is put back
// onto the plane. A folding wall (the rz axis) and a particle farther out, or more than h
// behind the plane, are left alone.
TEST(Boundaries, ARigidWallStopsTheApproachOfParticlesOnItAndKeepsTheirEnergy) {
  ParticleStore s;
  ParticleFields<2> f;
  fixtures::registerFields(s, f);
  const double h = 1.0e-3;
  // On the wall moving in; just above the hold moving in; on the wall moving out; on the wall
  // moving in, pulled out; a step across moving in; far behind (not the wall's).
  const Vec<2> x[] = {{0.0, 0.01 * h}, {0.0, 0.06 * h}, {0.0, 0.0},
                      {0.3, 0.04 * h}, {0.2, -0.1 * h}, {0.0, -2.0 * h}};
  const Vec<2> v[] = {{3.0, -4.0}, {3.0, -4.0}, {3.0, 4.0}, {-1.0, -2.0}, {1.0, -6.0}, {0.0, -1.0}};
  const Vec<2> a[] = {{1.0, -2.0}, {1.0, -2.0}, {1.0, -2.0}, {5.0, 7.0}, {0.0, -1.0}, {0.0, -1.0}};
  s.resizeLocal(6);
  for (std::size_t i = 0; i < 6; ++i) {
    s[f.x][i] = x[i], s[f.v][i] = v[i], s[f.a][i] = a[i];
    s[f.h][i] = h, s[f.e][i] = 10.0;
  }
  BoundaryConfig axis = wall({-1.0, 0.0}, {1.0, 0.0});
  axis.fold = true; // far from every particle's x, but a fold wall is never a hold
  solvers::Boundaries<2> b({axis, wall({0.0, 0.0}, {0.0, 1.0})}, s, f);
  b.holdAcceleration(s[f.x], s[f.h], s[f.a]);
  b.holdVelocity(s[f.x], s[f.h], s[f.v], s[f.e]);
  EXPECT_EQ(s[f.v][0], Vec<2>(3.0, 0.0));
  EXPECT_EQ(s[f.e][0], 10.0 + 0.5 * 16.0); // 1/2 m v_n^2 per unit mass, into heat
  EXPECT_EQ(s[f.a][0], Vec<2>(1.0, 0.0));
  EXPECT_EQ(s[f.v][1], v[1]); // beyond kHold h = 0.05 h
  EXPECT_EQ(s[f.a][1], a[1]);
  EXPECT_EQ(s[f.e][1], 10.0);
  EXPECT_EQ(s[f.v][2], v[2]); // leaving the wall
  EXPECT_EQ(s[f.a][2], Vec<2>(1.0, 0.0));
  EXPECT_EQ(s[f.v][3], Vec<2>(-1.0, 0.0));
  EXPECT_EQ(s[f.a][3], a[3]); // pulled away from the wall: free to go
  EXPECT_EQ(s[f.e][3], 10.0 + 0.5 * 4.0);
  EXPECT_EQ(s[f.x][4], Vec<2>(0.2, 0.0));
  EXPECT_EQ(s[f.v][4], Vec<2>(1.0, 0.0));
  EXPECT_EQ(s[f.e][4], 10.0 + 0.5 * 36.0);
  EXPECT_EQ(s[f.x][5], x[5]);
  EXPECT_EQ(s[f.v][5], v[5]);
  EXPECT_EQ(s[f.a][5], a[5]);
}

// A rigid wall's images carry the mirrored pressure and stress across the plane but no
// artificial viscosity: a fluid block spreading along the wall and closing on it (v = G x, the
// flow at a Taylor bar's face) gets from its images a force that does not depend on its
// velocities. As viscous neighbors the same images push the block off the wall and sideways
// as hard as the block's own viscosity acts (what held a Taylor bar's face layer 0.2 spacings
// above the wall and its face too narrow: decks/topics/taylor-bars.md).
TEST(Boundaries, ARigidWallsImagesExertNoViscosity) {
  SolverConfig cfg; // Monaghan's viscosity, alpha 1, beta 2
  Tensor<2> G;
  G << 2.0e3, 0.0, 0.0, -2.0e3; // 1/s: spreading along x, closing on the wall y = 0
  // The images' share of each owned particle's acceleration, for a velocity field and a choice
  // of which rows are wall images.
  double blockViscosity = 0.0; // the largest acceleration the block's own pairs give
  const auto imageShare = [&](const Tensor<2>& grad, bool viscousImages) {
    fixtures::SolverLattice free(6, cfg, false, grad), walled(6, cfg, false, grad);
    free.evaluate();
    walled.evaluate(); // p and cs of the owned particles, which their images copy
    solvers::Boundaries<2> b({wall({0.0, 0.0}, {0.0, 1.0})}, walled.store, walled.f);
    b.buildGhosts(walled.store, 2.0 * 1.5 * fixtures::SolverLattice::dp);
    EXPECT_EQ(b.firstWallImage(), walled.store.localCount());
    EXPECT_EQ(walled.store.ghostCount(), 18u); // the three rows within the support
    walled.evaluate(viscousImages ? std::numeric_limits<std::size_t>::max() : b.firstWallImage());
    std::vector<Vec<2>> share;
    for (std::size_t i = 0; i < free.store.localCount(); ++i) {
      share.push_back(walled.store[walled.f.a][i] - free.store[free.f.a][i]);
      blockViscosity = std::max(blockViscosity, free.store[free.f.a][i].norm());
    }
    return share;
  };
  const auto still = imageShare(Tensor<2>::Zero(), false);
  const auto moving = imageShare(G, false);
  const auto friction = imageShare(G, true);
  double scale = 0.0, viscous = 0.0;
  for (std::size_t i = 0; i < still.size(); ++i) scale = std::max(scale, still[i].norm());
  ASSERT_GT(scale, 0.0); // the pressure across the wall
  for (std::size_t i = 0; i < still.size(); ++i) {
    // The same to rounding (the sums add the same terms; 1e-12 of the largest share).
    EXPECT_NEAR(moving[i][0], still[i][0], 1e-12 * scale) << "particle " << i;
    EXPECT_NEAR(moving[i][1], still[i][1], 1e-12 * scale) << "particle " << i;
    viscous = std::max(viscous, (friction[i] - still[i]).norm());
  }
  // What viscous images would add: of the order of the block's own viscous forces (measured
  // 1.0 of their largest).
  EXPECT_GT(viscous, 0.5 * blockViscosity);
}
