// Rigid-wall images are made and refreshed from the field flags alone: positions mirrored
// across the plane, kReflectVector fields reflected (P v), kReflectTensor fields mirrored
// (P T P), everything else copied; in a corner the image of an image carries both reflections.
#include "spall/solvers/Boundaries.hpp"

#include <algorithm>
#include <gtest/gtest.h>

using namespace spall;

namespace {

BoundaryConfig wall(std::vector<double> point, std::vector<double> normal) {
  BoundaryConfig b;
  b.type = "rigid_wall";
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
  f.registerIn(s, {.strength = true, .corrected = true, .asph = true});
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
  f.registerIn(s, {.balsara = true, .strength = true});
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
