// Friends of friends across ranks (diagnostics/Fragments.hpp) on synthetic particles, against a
// brute-force union-find over all particles that every rank makes alike: the same fragments (the
// smallest id, the member count, the exact mass, velocity and non-periodic centre, the periodic
// centre to round-off), in the same order, and every owned particle's place in it. A random cloud
// near the percolation density gives fragments of every size, many straddling rank borders and the
// periodic x boundary; every seventh particle is "damaged" and links to nothing. Runs on any number
// of ranks (ctest: 1-5).
#include "spall/core/ParticleStore.hpp"
#include "spall/diagnostics/Fragments.hpp"
#include "spall/parallel/Decomposition.hpp"
#include "spall/parallel/HaloExchange.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <vector>

using namespace spall;

namespace {

constexpr std::size_t kN = 3000;
constexpr double kPeriod = 1.0; // x is periodic on [0, 1)

struct Cloud {
  ParticleStore s;
  Field<ParticleId> id;
  Field<Vec<3>> x, v;
  Field<std::int32_t> cost;
  Field<double> m, R;
  Field<ParticleId> label;
  Cloud() {
    id = s.add<ParticleId>("id");
    x = s.add<Vec<3>>("position");
    v = s.add<Vec<3>>("velocity");
    cost = s.add<std::int32_t>("cost");
    m = s.add<double>("mass");
    R = s.add<double>("link_radius");
    label = s.add<ParticleId>("label", 0);
  }
};

struct Particle {
  ParticleId id;
  Vec<3> x, v;
  double m, R;
  bool linkable;
};

std::vector<Particle> makeAll() {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Particle> all;
  for (std::size_t i = 0; i < kN; ++i) {
    const ParticleId id = 100 + 3 * i; // ids need not be contiguous
    all.push_back({id, Vec<3>(u(rng), u(rng), 0.2 * u(rng)), Vec<3>(u(rng), -u(rng), 0.0),
                   1.0 + 1e-6 * static_cast<double>(i % 97), 0.03 + 0.02 * u(rng), i % 7 != 0});
  }
  return all;
}

Vec<3> minimumImage(Vec<3> d) {
  d[0] -= kPeriod * std::round(d[0] / kPeriod);
  return d;
}

bool friends(const Particle& a, const Particle& b) {
  const double reach = 0.5 * (a.R + b.R);
  return a.linkable && b.linkable && minimumImage(a.x - b.x).squaredNorm() <= reach * reach;
}

// The catalogue the brute force finds, in the catalogue's order, and each id's place in it.
std::vector<diagnostics::Fragment> bruteForce(const std::vector<Particle>& all,
                                              std::map<ParticleId, std::int64_t>& place) {
  const std::size_t n = all.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (friends(all[i], all[j])) parent[std::max(find(i), find(j))] = std::min(find(i), find(j));
  // Members in id order (all is in id order), the first member is the smallest id.
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < n; ++i) groups[find(i)].push_back(i);
  std::vector<diagnostics::Fragment> out;
  // The fixed points findFragments uses: the largest |m|, |m x_d|, |m v_d| of all particles.
  double mMax = 0.0, mxMax[3] = {0, 0, 0}, mvMax[3] = {0, 0, 0};
  for (const auto& p : all) {
    mMax = std::max(mMax, p.m);
    for (int d = 0; d < 3; ++d) {
      mxMax[d] = std::max(mxMax[d], std::abs(p.m * p.x[d]));
      mvMax[d] = std::max(mvMax[d], std::abs(p.m * p.v[d]));
    }
  }
  const diagnostics::FixedPoint fixed(mMax);
  for (const auto& [root, members] : groups) {
    diagnostics::Fragment f;
    f.label = all[members.front()].id;
    f.particles = members.size();
    double mx0 = 0.0, msum = 0.0; // x is periodic: its centre in doubles
    diagnostics::Int128 q = 0, qmx[3] = {0, 0, 0}, qmv[3] = {0, 0, 0};
    for (const std::size_t k : members) {
      q += fixed.of(all[k].m);
      msum += all[k].m;
      const double x =
          all[k].x[0] - kPeriod * std::round((all[k].x[0] - all[members.front()].x[0]) / kPeriod);
      mx0 += all[k].m * x;
      for (int d = 0; d < 3; ++d) {
        qmx[d] += diagnostics::FixedPoint(mxMax[d]).of(all[k].m * all[k].x[d]);
        qmv[d] += diagnostics::FixedPoint(mvMax[d]).of(all[k].m * all[k].v[d]);
      }
    }
    f.mass = fixed.value(q);
    // A fragment spanning half the periodic box or more has no well-defined centre: flagged by
    // a NaN, and its centre is not compared.
    double lo = 1e300, hi = -1e300;
    for (const std::size_t k : members) {
      const double x =
          all[k].x[0] - kPeriod * std::round((all[k].x[0] - all[members.front()].x[0]) / kPeriod);
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
    f.x[0] = hi - lo >= 0.45 * kPeriod ? std::numeric_limits<double>::quiet_NaN() : mx0 / msum;
    for (int d = 0; d < 3; ++d) {
      if (d > 0) f.x[d] = diagnostics::FixedPoint(mxMax[d]).value(qmx[d]) / f.mass;
      f.v[d] = diagnostics::FixedPoint(mvMax[d]).value(qmv[d]) / f.mass;
    }
    out.push_back(f);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.mass != b.mass ? a.mass > b.mass : a.label < b.label;
  });
  std::map<ParticleId, std::int64_t> byLabel;
  for (std::size_t k = 0; k < out.size(); ++k) byLabel[out[k].label] = static_cast<std::int64_t>(k);
  for (std::size_t i = 0; i < n; ++i)
    place[all[i].id] = byLabel.at(all[find(i)].id); // root: the smallest
  return out;
}

} // namespace

TEST(Fragments, FriendsOfFriendsAcrossRanksAndPeriodicBoundsMatchBruteForce) {
  const std::vector<Particle> all = makeAll();
  std::map<ParticleId, std::int64_t> wantPlace;
  const std::vector<diagnostics::Fragment> want = bruteForce(all, wantPlace);

  Cloud c;
  c.s.resizeLocal(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    c.s[c.id][i] = all[i].id;
    c.s[c.x][i] = all[i].x;
    c.s[c.v][i] = all[i].v;
    c.s[c.m][i] = all[i].m;
    c.s[c.R][i] = all[i].R;
  }
  parallel::DecompositionConfig cfg;
  parallel::Decomposition<3> dec(MPI_COMM_WORLD, cfg, c.id, c.x, c.cost);
  dec.distributeInitial(c.s);
  parallel::HaloExchange<3> halo(MPI_COMM_WORLD, {parallel::PeriodicAxis{0, 0.0, kPeriod}});
  const std::size_t n = c.s.localCount();
  std::vector<double> reach(c.s[c.R].begin(), c.s[c.R].begin() + static_cast<std::ptrdiff_t>(n));
  const std::size_t fields[] = {c.id.index, c.x.index, c.v.index, c.m.index, c.R.index};
  halo.build(c.s, c.x, reach, fields);
  const std::size_t rows = c.s.size();

  // The pairs a neighbor search would give: every row within either particle's reach.
  neighbors::NeighborList nl;
  nl.offsets.push_back(0);
  const auto x = c.s[c.x];
  const auto R = c.s[c.R];
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::uint32_t> row;
    for (std::size_t j = 0; j < rows; ++j)
      if (j != i && (x[i] - x[j]).norm() < std::max(R[i], R[j]))
        row.push_back(static_cast<std::uint32_t>(j));
    nl.append(row);
  }
  std::map<ParticleId, bool> linkableOf;
  for (const auto& p : all) linkableOf[p.id] = p.linkable;
  std::vector<std::uint8_t> linkable(rows);
  for (std::size_t r = 0; r < rows; ++r) linkable[r] = linkableOf.at(c.s[c.id][r]);

  diagnostics::FragmentInput<3> in;
  in.id = c.s[c.id];
  in.x = c.s[c.x];
  in.v = c.s[c.v];
  in.m = c.s[c.m];
  in.linkRadius = c.s[c.R];
  in.linkable = linkable;
  in.owned = n;
  in.pairs = &nl;
  in.period = {kPeriod, 0.0, 0.0};
  const std::size_t column[] = {c.label.index};
  const auto cat = diagnostics::findFragments<3>(
      in,
      [&](std::vector<ParticleId>& labels) {
        const auto carrier = c.s[c.label];
        for (std::size_t i = 0; i < n; ++i) carrier[i] = labels[i];
        halo.refresh(c.s, column);
        for (std::size_t r = n; r < rows; ++r) labels[r] = carrier[r];
      },
      MPI_COMM_WORLD);

  EXPECT_EQ(cat.count, want.size());
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < n; ++i) wrong += cat.index[i] != wantPlace.at(c.s[c.id][i]);
  EXPECT_EQ(wrong, 0u) << "owned particles in the wrong fragment";
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  ASSERT_EQ(cat.fragments.size(), want.size());
  std::size_t largest = 0, straddling = 0;
  for (std::size_t k = 0; k < want.size(); ++k) {
    const auto &a = cat.fragments[k], &b = want[k];
    EXPECT_EQ(a.label, b.label) << k;
    EXPECT_EQ(a.particles, b.particles) << k;
    EXPECT_EQ(a.mass, b.mass) << k; // exact sums on both sides: bit for bit
    // Velocities and the centre along the axes that are not periodic: exact sums, bit for bit.
    // Along the periodic x the shares of ranks are summed in another order: round-off (1e-13 of
    // the box).
    if (!std::isnan(b.x[0])) {
      EXPECT_NEAR(a.x[0], b.x[0], 1e-13) << k;
    }
    for (int d = 0; d < 3; ++d) {
      if (d > 0) {
        EXPECT_EQ(a.x[d], b.x[d]) << k << " axis " << d;
      }
      EXPECT_EQ(a.v[d], b.v[d]) << k << " axis " << d;
    }
    largest = std::max<std::size_t>(largest, b.particles);
    straddling += b.particles > 1 && (b.x[0] < 0.0 || b.x[0] > kPeriod - 0.05 || b.x[0] < 0.05);
  }
  // The cloud is what the test needs: big fragments, and fragments at the periodic boundary.
  EXPECT_GT(largest, 50u);
  EXPECT_GT(straddling, 3u);
}
