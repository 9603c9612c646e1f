// The parallel infrastructure on synthetic particles (no physics): weighted cuts, migration that
// never loses or duplicates a particle however far it jumps, and halo completeness against a
// brute-force pair search over all ranks' particles. Runs on any number of ranks (ctest: 2 and 4).
#include "spall/core/ParticleStore.hpp"
#include "spall/core/SymmetricEigen.hpp"
#include "spall/parallel/Decomposition.hpp"
#include "spall/parallel/HaloExchange.hpp"
#include "spall/parallel/VirtualRanks.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <vector>

using namespace spall;
using namespace spall::parallel;

namespace {

int rankOf() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int sizeOf() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

// A store with the fields the decomposition needs plus a payload that only this test knows: it
// must migrate with its particle untouched.
struct Cloud {
  ParticleStore s;
  Field<ParticleId> id;
  Field<Vec<3>> x;
  Field<std::int32_t> cost;
  Field<double> payload;
  Field<Vec<3>> tag;
  Cloud() {
    id = s.add<ParticleId>("id");
    x = s.add<Vec<3>>("position");
    cost = s.add<std::int32_t>("cost");
    payload = s.add<double>("payload");
    tag = s.add<Vec<3>>("tag");
  }
  static double payloadOf(ParticleId i) { return std::sqrt(static_cast<double>(i) + 0.5); }
};

// Every rank generates all n particles (as the run does), then distributes.
void fillAll(Cloud& c, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  c.s.resizeLocal(n);
  for (std::size_t i = 0; i < n; ++i) {
    c.s[c.id][i] = 1000 + i;
    c.s[c.x][i] = Vec<3>(u(rng), u(rng), 0.2 * u(rng));
    c.s[c.payload][i] = Cloud::payloadOf(1000 + i);
    c.s[c.tag][i] = Vec<3>(static_cast<double>(i), -1.0, 2.0);
  }
}

// All ids on every rank: sorted, with payload checks done by the caller.
std::vector<ParticleId> allIds(const Cloud& c) {
  const int size = sizeOf();
  int n = static_cast<int>(c.s.localCount());
  std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size));
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < size; ++r)
    displs[static_cast<std::size_t>(r)] = total, total += counts[static_cast<std::size_t>(r)];
  std::vector<ParticleId> mine(c.s[c.id].begin(), c.s[c.id].begin() + n),
      all(static_cast<std::size_t>(total));
  MPI_Allgatherv(mine.data(), n, MPI_UINT64_T, all.data(), counts.data(), displs.data(),
                 MPI_UINT64_T, MPI_COMM_WORLD);
  std::sort(all.begin(), all.end());
  return all;
}

} // namespace

TEST(Partition, WeightedCutsBalanceSyntheticCosts) {
  // Random keys with costs 1..100 (a heavy-tailed load): every rank's share of the total lies
  // within one particle's largest cost of W/R, the best any contiguous cut can guarantee.
  const int rank = rankOf(), size = sizeOf();
  std::mt19937_64 rng(7 + static_cast<std::uint64_t>(rank));
  std::vector<std::uint64_t> keys(5000), cost(5000);
  for (auto& k : keys) k = rng() % kKeyEnd;
  std::sort(keys.begin(), keys.end());
  for (auto& w : cost) w = 1 + rng() % 100;
  const auto cuts = weightedSplitters(MPI_COMM_WORLD, keys, cost);
  ASSERT_EQ(cuts.size(), static_cast<std::size_t>(size));
  const auto own = KeyOwnership::contiguous(cuts);
  std::vector<std::uint64_t> share(static_cast<std::size_t>(size), 0);
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < keys.size(); ++i)
    share[static_cast<std::size_t>(own.owner(keys[i]))] += cost[i], total += cost[i];
  MPI_Allreduce(MPI_IN_PLACE, share.data(), size, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  for (int r = 0; r < size; ++r)
    EXPECT_NEAR(static_cast<double>(share[static_cast<std::size_t>(r)]),
                static_cast<double>(total) / size, 100.0)
        << "rank " << r;
  // The one-process cut (`spall plan`'s) from every rank's keys at once: the same splitters.
  std::vector<std::uint64_t> allKeys(keys.size() * static_cast<std::size_t>(size)),
      allCost(allKeys.size());
  MPI_Allgather(keys.data(), static_cast<int>(keys.size()), MPI_UINT64_T, allKeys.data(),
                static_cast<int>(keys.size()), MPI_UINT64_T, MPI_COMM_WORLD);
  MPI_Allgather(cost.data(), static_cast<int>(cost.size()), MPI_UINT64_T, allCost.data(),
                static_cast<int>(cost.size()), MPI_UINT64_T, MPI_COMM_WORLD);
  std::vector<std::size_t> order(allKeys.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return allKeys[a] < allKeys[b]; });
  std::vector<std::uint64_t> sortedKeys, sortedCost;
  for (auto i : order) sortedKeys.push_back(allKeys[i]), sortedCost.push_back(allCost[i]);
  EXPECT_EQ(splittersOf(sortedKeys, sortedCost, size), cuts);
  // Unit costs with runs of equal keys (particles in one cell), and more ranks than keys.
  const std::vector<std::uint64_t> dup{3, 3, 3, 5, 5, 9, 9, 9, 9, 12}, unit(dup.size(), 1);
  EXPECT_EQ(splittersOf(dup, unit, 4), (std::vector<std::uint64_t>{0, 4, 6, 10}));
  EXPECT_EQ(splittersOf(std::vector<std::uint64_t>{7}, std::vector<std::uint64_t>{1}, 3),
            (std::vector<std::uint64_t>{0, 8, 8})); // targets ceil(W/3) = ceil(2W/3) = 1
}

TEST(Decomposition, ThousandRebalancesOfARandomCloudLoseNothing) {
  Cloud c;
  const std::size_t n = 3000;
  fillAll(c, n, 42);
  DecompositionConfig cfg;
  Decomposition<3> dec(MPI_COMM_WORLD, cfg, c.id, c.x, c.cost);
  dec.distributeInitial(c.s);
  std::vector<ParticleId> expected(n);
  for (std::size_t i = 0; i < n; ++i) expected[i] = 1000 + i;
  std::mt19937_64 rng(99 + static_cast<std::uint64_t>(rankOf()));
  std::normal_distribution<double> step(0.0, 0.02);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int farthest = 0;
  for (int it = 0; it < 1000; ++it) {
    auto x = c.s[c.x];
    auto cost = c.s[c.cost];
    for (std::size_t i = 0; i < c.s.localCount(); ++i) {
      x[i] += Vec<3>(step(rng), step(rng), step(rng));
      // One particle in a hundred jumps anywhere: across any number of domains.
      if (u(rng) < 0.01) x[i] = Vec<3>(u(rng), u(rng), 0.2 * u(rng));
      cost[i] = 1 + static_cast<std::int32_t>(u(rng) * 50); // changing load
    }
    farthest = std::max(farthest, dec.migrate(c.s, it).maxRankDistance);
    dec.rebalance(c.s);
    std::uint64_t count = c.s.localCount();
    MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    ASSERT_EQ(count, n) << "after rebalance " << it;
    if (it % 100 == 99) {
      ASSERT_EQ(allIds(c), expected) << "after rebalance " << it;
    }
  }
  // Every field came along with its particle.
  for (std::size_t i = 0; i < c.s.localCount(); ++i) {
    const ParticleId id = c.s[c.id][i];
    EXPECT_EQ(c.s[c.payload][i], Cloud::payloadOf(id));
    EXPECT_EQ(c.s[c.tag][i][0], static_cast<double>(id - 1000));
  }
  if (sizeOf() >= 4) {
    EXPECT_GE(farthest, 2) << "jumps should cross several domains";
  }
}

TEST(Decomposition, MoreRanksThanParticles) {
  Cloud c;
  fillAll(c, 3, 5); // fewer particles than ranks when run on 4
  DecompositionConfig cfg;
  Decomposition<3> dec(MPI_COMM_WORLD, cfg, c.id, c.x, c.cost);
  dec.distributeInitial(c.s);
  for (int it = 0; it < 20; ++it) {
    for (auto& p : c.s[c.x]) p += Vec<3>(0.3, -0.1, 0.05);
    dec.migrate(c.s, it);
    dec.rebalance(c.s);
  }
  EXPECT_EQ(allIds(c), (std::vector<ParticleId>{1000, 1001, 1002}));
  HaloExchange<3> halo(MPI_COMM_WORLD, {});
  std::vector<double> reach(c.s.localCount(), 10.0);
  const std::size_t fields[] = {c.id.index, c.x.index};
  halo.build(c.s, c.x, reach, fields);
  // Everybody reaches everybody: a rank that owns particles sees all 3, owned or ghost; a rank
  // with an empty domain needs (and gets) nothing.
  EXPECT_EQ(c.s.size(), c.s.localCount() > 0 ? 3u : 0u);
}

// The halo is complete: for every owned particle, the particles within max(reach_i, reach_j)
// among owned + ghosts are exactly those a brute-force search over all ranks' particles (and
// their periodic images) finds.
TEST(HaloExchange, CompleteAgainstBruteForceWithPeriodicAxis) {
  Cloud c;
  const std::size_t n = 2000;
  fillAll(c, n, 11);
  Field<double> reachField = c.s.add<double>("reach");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.03, 0.12);
  for (std::size_t i = 0; i < n; ++i) c.s[reachField][i] = u(rng); // same on every rank
  DecompositionConfig cfg;
  Decomposition<3> dec(MPI_COMM_WORLD, cfg, c.id, c.x, c.cost);
  dec.distributeInitial(c.s);
  // Everybody's particles, for the brute force.
  std::map<ParticleId, std::pair<Vec<3>, double>> all;
  {
    Cloud g;
    fillAll(g, n, 11);
    for (std::size_t i = 0; i < n; ++i) all[g.s[g.id][i]] = {g.s[g.x][i], 0.0};
    std::mt19937_64 rng2(3);
    for (std::size_t i = 0; i < n; ++i) all[1000 + i].second = u(rng2);
  }
  const PeriodicAxis px{0, 0.0, 1.0};
  HaloExchange<3> halo(MPI_COMM_WORLD, {px});
  const std::size_t local = c.s.localCount();
  std::vector<double> reach(c.s[reachField].begin(), c.s[reachField].begin() + local);
  const std::size_t fields[] = {c.id.index, c.x.index, reachField.index};
  halo.build(c.s, c.x, reach, fields);
  const auto id = c.s[c.id];
  const auto x = c.s[c.x];
  const auto rj = c.s[reachField];
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < local; ++i) {
    std::multiset<std::pair<ParticleId, long>> seen, want;
    for (std::size_t j = 0; j < c.s.size(); ++j) {
      if (j == i) continue;
      const double r = (x[i] - x[j]).norm();
      if (r < std::max(rj[i], rj[j])) seen.insert({id[j], std::lround(x[j][0] - x[i][0])});
    }
    for (const auto& [jd, pr] : all) {
      for (double shift : {-1.0, 0.0, 1.0}) {
        if (jd == id[i] && shift == 0.0) continue;
        const Vec<3> xj = pr.first + Vec<3>(shift, 0.0, 0.0);
        if ((x[i] - xj).norm() < std::max(rj[i], pr.second))
          want.insert({jd, std::lround(xj[0] - x[i][0])});
      }
    }
    if (seen != want) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0u) << "owned particles whose neighbor set is incomplete or padded";
  std::uint64_t ghosts = halo.ghosts();
  MPI_Allreduce(MPI_IN_PLACE, &ghosts, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_GT(ghosts, 0u);
}

namespace {
// An ellipsoidal support per particle, from its id alone (the same on every rank): for even ids
// axes 0.01-0.12 (aspect ratios up to 12) in a random orientation, for odd ids discs 0.01 thin
// along x and 0.1 wide, whose bounding boxes are much tighter than their spheres along x (the
// periodic axis, and a direction the partition cuts). The support is |H x| < 1.
Tensor<3> ellipsoidOf(ParticleId id) {
  if (id % 2) return Vec<3>(100.0, 10.0, 10.0).asDiagonal();
  std::mt19937_64 rng(id * 7919 + 1);
  std::uniform_real_distribution<double> axis(0.01, 0.12);
  std::normal_distribution<double> g(0.0, 1.0);
  const Tensor<3> Q =
      Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
  const Vec<3> lengths(axis(rng), axis(rng), axis(rng));
  return Q * lengths.cwiseInverse().asDiagonal() * Q.transpose();
}
} // namespace

// The halo with ellipsoidal supports (enclosing spheres and bounding boxes) is complete: every
// owned particle sees exactly the pairs where either ellipsoid covers the other particle, as a
// brute force over all particles and their periodic images finds. And it sends fewer ghosts than
// the spheres alone would.
TEST(HaloExchange, EllipsoidBoxesCompleteAgainstBruteForce) {
  Cloud c;
  const std::size_t n = 2000;
  fillAll(c, n, 13);
  std::map<ParticleId, std::pair<Vec<3>, Tensor<3>>> all;
  {
    Cloud g;
    fillAll(g, n, 13);
    for (std::size_t i = 0; i < n; ++i)
      all[g.s[g.id][i]] = {g.s[g.x][i], ellipsoidOf(g.s[g.id][i])};
  }
  DecompositionConfig cfg;
  Decomposition<3> dec(MPI_COMM_WORLD, cfg, c.id, c.x, c.cost);
  dec.distributeInitial(c.s);
  const PeriodicAxis px{0, 0.0, 1.0};
  HaloExchange<3> halo(MPI_COMM_WORLD, {px});
  const std::size_t local = c.s.localCount();
  std::vector<Vec<3>> box(local);
  std::vector<double> sphere(local);
  for (std::size_t i = 0; i < local; ++i) {
    const Tensor<3>& H = all.at(c.s[c.id][i]).second;
    box[i] = H.inverse().rowwise().norm();
    sphere[i] = 1.0 / symmetricEigen<3>(H).values[0]; // the longest axis
  }
  const std::size_t fields[] = {c.id.index, c.x.index};
  halo.build(c.s, c.x, sphere, std::span<const Vec<3>>(box), fields);
  const auto id = c.s[c.id];
  const auto x = c.s[c.x];
  const auto within = [](const Tensor<3>& Hi, const Tensor<3>& Hj, const Vec<3>& xij) {
    return (Hi * xij).norm() < 1.0 || (Hj * xij).norm() < 1.0;
  };
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < local; ++i) {
    const Tensor<3>& Hi = all.at(id[i]).second;
    std::multiset<std::pair<ParticleId, long>> seen, want;
    for (std::size_t j = 0; j < c.s.size(); ++j)
      if (j != i && within(Hi, all.at(id[j]).second, x[i] - x[j]))
        seen.insert({id[j], std::lround(x[j][0] - x[i][0])});
    for (const auto& [jd, pj] : all)
      for (double shift : {-1.0, 0.0, 1.0}) {
        if (jd == id[i] && shift == 0.0) continue;
        const Vec<3> xj = pj.first + Vec<3>(shift, 0.0, 0.0);
        if (within(Hi, pj.second, x[i] - xj)) want.insert({jd, std::lround(xj[0] - x[i][0])});
      }
    if (seen != want) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0u) << "owned particles whose neighbor set is incomplete or padded";
  std::uint64_t ghosts[2] = {halo.ghosts(), 0};
  halo.build(c.s, c.x, sphere, fields);
  ghosts[1] = halo.ghosts();
  MPI_Allreduce(MPI_IN_PLACE, ghosts, 2, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_GT(ghosts[0], 0u);
  EXPECT_LT(ghosts[0], ghosts[1]) << "boxes should select fewer ghosts than enclosing spheres";
}

// `spall plan`'s virtual ranks make what the run makes: a one-process cut of every particle for
// this run's rank count owns the same particles per rank and sends each rank the same ghosts as
// Decomposition::distributeInitial and HaloExchange::build do here, with spheres and with
// ellipsoids' boxes, across a periodic axis.
TEST(VirtualRanks, SameOwnedAndGhostsAsTheDecompositionAndHalo) {
  const int rank = rankOf(), size = sizeOf();
  for (const bool round : {true, false}) {
    Cloud c;
    const std::size_t n = 3000;
    fillAll(c, n, 17);
    std::vector<Vec<3>> xAll(c.s[c.x].begin(), c.s[c.x].begin() + n);
    std::vector<ParticleId> idAll(c.s[c.id].begin(), c.s[c.id].begin() + n);
    // Reaches from the id alone: spheres 0.02-0.08, or boxes with different half-widths.
    const auto boxOf = [round](ParticleId id) {
      const double r = 0.02 + 0.06 * static_cast<double>(id % 7) / 6.0;
      return round ? Vec<3>(r, r, r) : Vec<3>(r, 0.5 * r, 0.25 * r);
    };
    std::vector<Vec<3>> reachAll(n);
    std::vector<double> radiusAll(n);
    for (std::size_t i = 0; i < n; ++i)
      reachAll[i] = boxOf(idAll[i]), radiusAll[i] = reachAll[i].norm();
    if (round)
      for (std::size_t i = 0; i < n; ++i) radiusAll[i] = reachAll[i][0];
    const PeriodicAxis px{0, 0.0, 1.0};

    DecompositionConfig cfg;
    Decomposition<3> dec(MPI_COMM_WORLD, cfg, c.id, c.x, c.cost);
    dec.distributeInitial(c.s);
    const std::size_t local = c.s.localCount();
    std::vector<Vec<3>> box(local);
    std::vector<double> radius(local);
    for (std::size_t i = 0; i < local; ++i) {
      box[i] = boxOf(c.s[c.id][i]);
      radius[i] = round ? box[i][0] : box[i].norm();
    }
    HaloExchange<3> halo(MPI_COMM_WORLD, {px});
    const std::size_t fields[] = {c.id.index, c.x.index};
    if (round)
      halo.build(c.s, c.x, radius, fields);
    else
      halo.build(c.s, c.x, radius, std::span<const Vec<3>>(box), fields);
    std::uint64_t mine[2] = {local, halo.ghosts()};
    std::vector<std::uint64_t> real(2 * static_cast<std::size_t>(size));
    MPI_Allgather(mine, 2, MPI_UINT64_T, real.data(), 2, MPI_UINT64_T, MPI_COMM_WORLD);

    VirtualParticles<3> vp;
    vp.x = xAll, vp.id = idAll, vp.reach = reachAll, vp.radius = radiusAll, vp.round = round;
    vp.periodic = {px};
    const auto planned = VirtualRanks<3>(vp).cut(size);
    std::uint64_t ghosts = 0;
    for (int r = 0; r < size; ++r) {
      const auto& q = planned[static_cast<std::size_t>(r)];
      EXPECT_EQ(q.owned, real[2 * static_cast<std::size_t>(r)]) << "rank " << r;
      EXPECT_EQ(q.ghosts, real[2 * static_cast<std::size_t>(r) + 1])
          << "rank " << r << (round ? " (spheres)" : " (boxes)");
      ghosts += q.ghosts;
      // Every rank sends to and receives from somebody here (the periodic cloud is connected).
      if (size > 1) {
        EXPECT_GT(q.neighbors, 0u);
      }
    }
    EXPECT_GT(ghosts, 0u);
    if (rank == 0 && size > 1) {
      EXPECT_GT(planned[0].sent, 0u) << "rank 0 sends ghosts to its neighbours";
    }
  }
}
