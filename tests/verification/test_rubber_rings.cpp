// The colliding rubber rings of Gray, Monaghan & Swift (2001) (Owen 2010, Fig. 6): the rings must
// bounce and separate without fracturing or clumping (the tensile instability).
#include "RunDeck.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>

using namespace spall;
using namespace spall::verification;

namespace {

constexpr double v0 = 50.268; // 0.059 c0, each ring

struct RingState {
  double cx[2] = {0, 0}, vx[2] = {0, 0};
  double minPair = 1e300;      // closest two particles of one ring
  std::size_t detached = 0;    // particles outside their ring's largest piece (links < 1.5 dp)
  std::size_t onOtherRing = 0; // particles nearer to the other ring than to their own
};

RingState analyse(const io::SnapshotData& s, double dp) {
  RingState r;
  const auto& x = s.fields.at("position");
  const auto& v = s.fields.at("velocity");
  const auto& m = s.fields.at("mass");
  const auto& body = s.fields.at("body");
  double mass[2] = {0, 0};
  for (std::size_t i = 0; i < s.count; ++i) {
    const int b = static_cast<int>(body[i]);
    mass[b] += m[i];
    r.cx[b] += m[i] * x[2 * i];
    r.vx[b] += m[i] * v[2 * i];
  }
  for (int b = 0; b < 2; ++b) r.cx[b] /= mass[b], r.vx[b] /= mass[b];
  // All pairs: a few thousand particles.
  std::vector<std::vector<std::uint32_t>> links(s.count);
  for (std::size_t i = 0; i < s.count; ++i) {
    double own = 1e300, other = 1e300;
    for (std::size_t j = 0; j < s.count; ++j) {
      if (j == i) continue;
      const double d = std::hypot(x[2 * i] - x[2 * j], x[2 * i + 1] - x[2 * j + 1]);
      if (body[j] == body[i]) {
        own = std::min(own, d);
        if (d < 1.5 * dp) links[i].push_back(static_cast<std::uint32_t>(j));
      } else {
        other = std::min(other, d);
      }
    }
    r.minPair = std::min(r.minPair, own);
    r.onOtherRing += other < own;
  }
  // Pieces of each ring: particles linked by distances < 1.5 dp (lattice neighbors are 1 dp
  // apart, a crack opens wider). Everything outside a ring's largest piece is detached.
  std::vector<int> piece(s.count, -1);
  std::vector<std::size_t> size;
  for (std::size_t i = 0; i < s.count; ++i) {
    if (piece[i] >= 0) continue;
    const int id = static_cast<int>(size.size());
    std::vector<std::uint32_t> stack{static_cast<std::uint32_t>(i)};
    piece[i] = id;
    std::size_t n = 0;
    while (!stack.empty()) {
      const std::uint32_t a = stack.back();
      stack.pop_back();
      ++n;
      for (std::uint32_t b : links[a])
        if (piece[b] < 0) piece[b] = id, stack.push_back(b);
    }
    size.push_back(n);
  }
  for (int b = 0; b < 2; ++b) {
    std::size_t total = 0, largest = 0;
    for (std::size_t i = 0; i < s.count; ++i) total += static_cast<int>(body[i]) == b;
    for (std::size_t i = 0; i < s.count; ++i)
      if (static_cast<int>(body[i]) == b) largest = std::max(largest, size[piece[i]]);
    r.detached += total - largest;
  }
  return r;
}

// Runs the deck and checks every snapshot; returns the last state.
RingState runAndCheck(const std::vector<std::string>& overrides, const std::string& tag, double dp,
                      double minPairFraction) {
  int rc = -1;
  const auto dir = runSpall(deckPath("rubber_rings_2d.toml"), overrides, tag, &rc);
  EXPECT_EQ(rc, 0);
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir / "snapshots"))
    if (e.path().extension() == ".h5") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  EXPECT_GE(files.size(), 10u);
  RingState last;
  std::size_t maxDetached = 0;
  double minPair = 1e300;
  for (const auto& f : files) {
    const auto s = io::readSnapshot(f);
    last = analyse(s, dp);
    EXPECT_GE(last.minPair, minPairFraction * dp) << "clumping at t = " << s.time;
    // Fracture: a ring in more than one piece. A stray surface particle squeezed out at the
    // edge of the contact may count; a crack detaches hundreds.
    EXPECT_LE(last.detached, 4u) << "particles torn off at t = " << s.time;
    maxDetached = std::max(maxDetached, last.detached);
    minPair = std::min(minPair, last.minPair);
    // The bodies are symmetric: the two rings mirror each other.
    EXPECT_NEAR(last.cx[0], -last.cx[1], 1e-9) << "t = " << s.time;
  }
  const auto h = readHistory(dir);
  const double e0 = h.at("total_energy").front();
  double drift = 0.0;
  for (double e : h.at("total_energy")) drift = std::max(drift, std::abs(e - e0) / e0);
  // The scheme conserves energy to the time-integration error (pair-wise exact in the rates,
  // artificial stress included); measured 1e-6. 1e-4 still flags a non-conservative term, which
  // would move it by the ~0.5 of the kinetic energy the collision converts.
  EXPECT_LT(drift, 1e-4);
  std::printf("[ measured ] closest pair %.3f dp, most detached %zu, energy drift %.2e, end: ring "
              "velocities %.2f / %.2f m/s, %zu particles on the other ring\n",
              minPair / dp, maxDetached, drift, last.vx[0], last.vx[1], last.onOtherRing);
  std::filesystem::remove_all(dir);
  return last;
}

} // namespace

// 1.33 mm spacing (resolution 0.75: 7.5 particles across a ring), to 1.8 ms: through contact,
// maximum compression and the separation. Measured: closest pair 0.47 dp, rings leaving each
// other at 33 m/s (restitution 0.66), 2 particles left on the other ring.
TEST(RubberRings, BounceAndSeparateWithoutClumpingOrFracture) {
  const double dp = 1.0e-3 / 0.75;
  const RingState end = runAndCheck(
      {"run.resolution=0.75", "run.end_time=1.8e-3", "output.every=1.0e-4"}, "rings", dp, 0.4);
  // Separating: each ring moves back out. Restitution > 0.5: an elastic ring keeps most of the
  // approach speed (measured 0.66; the rest rings on as vibration); a clumped or welded pair
  // of rings comes nowhere near it.
  EXPECT_LT(end.vx[0], -0.5 * v0);
  EXPECT_GT(end.vx[1], 0.5 * v0);
  // No contact algorithm: particles that touched under tension may stay on the other ring; a
  // handful, not a weld (measured 2 of 2466).
  EXPECT_LE(end.onOtherRing, 12u);
}

// Several bounces across the periodic boundary at 1 mm spacing: the rings stay intact.
TEST(RubberRingsLong, SeveralBouncesStayStable) {
  const double dp = 1.0e-3;
  const RingState end =
      runAndCheck({"run.end_time=8.0e-3", "output.every=2.0e-4"}, "rings_long", dp, 0.4);
  EXPECT_LE(end.onOtherRing, 40u);
}

// The instability itself, so that the test above can fail: n_h = 1.2 without artificial stress
// pairs particles up before the rings even rebound (measured 0.02 dp at 0.8 ms).
TEST(RubberRingsLong, WithoutArtificialStressTheRingsClump) {
  int rc = -1;
  const auto dir = runSpall(deckPath("rubber_rings_2d.toml"),
                            {"solver.nodes_per_h=1.2", "solver.artificial_stress.epsilon=0",
                             "run.end_time=1.0e-3", "output.every=2.0e-4"},
                            "rings_clump", &rc);
  ASSERT_EQ(rc, 0);
  const auto s = io::readSnapshot(lastSnapshot(dir));
  EXPECT_LT(analyse(s, 1.0e-3).minPair, 0.2e-3);
  std::filesystem::remove_all(dir);
}
