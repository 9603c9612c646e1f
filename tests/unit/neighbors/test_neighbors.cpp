// The cell-list neighbor search against brute force, with unequal h and ghosts.
#include "spall/neighbors/NeighborList.hpp"

#include "spall/core/Threads.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <random>
#include <set>

using namespace spall;

namespace {
template <int Dim> void compareWithBruteForce(std::size_t n, std::size_t owned) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0), hd(0.02, 0.08);
  std::vector<Vec<Dim>> x(n);
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) x[i][d] = u(rng);
    h[i] = hd(rng);
  }
  x[n - 1] *= 50.0; // a far-flung particle must not blow up the grid
  neighbors::CellGrid<Dim> grid;
  neighbors::NeighborList nl;
  neighbors::buildNeighborList<Dim>(x, h, owned, 2.0, grid, nl);
  for (std::size_t i = 0; i < owned; ++i) {
    std::set<std::uint32_t> expect;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double reach = 2.0 * std::max(h[i], h[j]);
      if ((x[i] - x[j]).squaredNorm() < reach * reach) expect.insert(static_cast<std::uint32_t>(j));
    }
    const auto got = nl.row(i);
    ASSERT_EQ(std::set<std::uint32_t>(got.begin(), got.end()), expect) << "particle " << i;
    ASSERT_EQ(got.size(), expect.size()) << "a neighbor listed twice for particle " << i;
  }
}
} // namespace

TEST(NeighborList, MatchesBruteForce1D) {
  compareWithBruteForce<1>(400, 350);
}
TEST(NeighborList, MatchesBruteForce2D) {
  compareWithBruteForce<2>(1500, 1200);
}
TEST(NeighborList, MatchesBruteForce3D) {
  compareWithBruteForce<3>(3000, 2500);
}

namespace {
// Ellipsoidal supports (ASPH): random orientations, axes 0.01-0.1 (aspect ratios up to 10). The
// list must hold exactly the pairs where either support |H x| < 2 covers the other particle;
// the sphere of the longest axis would list up to 10^(Dim-1) times as many.
template <int Dim> void compareEllipsoidsWithBruteForce(std::size_t n, std::size_t owned) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), axis(0.01, 0.1);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec<Dim>> x(n);
  std::vector<Tensor<Dim>> H(n);
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) x[i][d] = u(rng);
    Tensor<Dim> Q;
    if constexpr (Dim == 2)
      Q = Eigen::Rotation2Dd(6.283185307179586 * u(rng)).toRotationMatrix();
    else
      Q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    Vec<Dim> lengths;
    for (int d = 0; d < Dim; ++d) lengths[d] = axis(rng);
    H[i] = Q * lengths.cwiseInverse().asDiagonal() * Q.transpose();
    h[i] = lengths.maxCoeff();
  }
  neighbors::CellGrid<Dim> grid;
  neighbors::NeighborList nl;
  neighbors::buildNeighborList<Dim>(x, h, std::span<const Tensor<Dim>>(H), owned, 2.0, grid, nl);
  std::size_t pairs = 0, sphere = 0;
  for (std::size_t i = 0; i < owned; ++i) {
    std::set<std::uint32_t> expect;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Vec<Dim> xij = x[i] - x[j];
      if ((H[i] * xij).norm() < 2.0 || (H[j] * xij).norm() < 2.0)
        expect.insert(static_cast<std::uint32_t>(j));
      const double reach = 2.0 * std::max(h[i], h[j]);
      sphere += xij.squaredNorm() < reach * reach;
    }
    const auto got = nl.row(i);
    ASSERT_EQ(std::set<std::uint32_t>(got.begin(), got.end()), expect) << "particle " << i;
    ASSERT_EQ(got.size(), expect.size()) << "a neighbor listed twice for particle " << i;
    pairs += got.size();
  }
  EXPECT_LT(pairs, sphere); // the ellipses, not their enclosing spheres
}
} // namespace

TEST(NeighborList, EllipsoidalSupportsMatchBruteForce2D) {
  compareEllipsoidsWithBruteForce<2>(1500, 1200);
}
TEST(NeighborList, EllipsoidalSupportsMatchBruteForce3D) {
  compareEllipsoidsWithBruteForce<3>(3000, 2500);
}

namespace {
// The search in parallel chunks must give the lists one sequential pass gives, entry for entry
// (not only the same sets): the force loop adds its neighbors in list order, and a different
// order changes the sums' last bits. Unequal h (pairs found from the larger support's side, the
// `extra` groups merged into rows) and ghosts past the owned rows, which chunk boundaries split.
template <int Dim> void compareThreadCounts(bool ellipsoids) {
  const std::size_t n = 4000, owned = 3100;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0), hd(0.02, 0.08);
  std::vector<Vec<Dim>> x(n);
  std::vector<double> h(n);
  std::vector<Tensor<Dim>> H(n);
  std::vector<ParticleId> id(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) x[i][d] = u(rng);
    h[i] = hd(rng);
    Vec<Dim> axes;
    for (int d = 0; d < Dim; ++d) axes[d] = hd(rng);
    H[i] = axes.cwiseInverse().asDiagonal();
    if (ellipsoids) h[i] = axes.maxCoeff();
    id[i] = static_cast<ParticleId>((i * 7919) % n); // rows not in id order
  }
  const neighbors::CanonicalOrder<Dim> order{id, x};
  // Builds into one list, as a run's steps: the first (no estimate of the chunks' shares yet) on
  // one thread; then into regions sized by the last build; supports 30% wider (the chunks
  // overflow their regions, spill and move up); only the lower half's supports wider again
  // (chunks moving up and down in one join); fewer owned rows and particles, then more (rows
  // past the last build's estimated from its mean); none owned; none at all.
  struct Step {
    double scale, lowerScale;
    std::size_t count, ownedRows;
  };
  const std::vector<Step> steps = {{1.0, 1.0, n, owned},
                                   {1.0, 1.0, n, owned},
                                   {1.3, 1.3, n, owned},
                                   {1.0, 1.4, n, owned},
                                   {1.0, 1.0, n - 700, owned - 600},
                                   {1.1, 1.1, n, owned},
                                   {1.0, 1.0, n, 0},
                                   {1.0, 1.0, 0, 0}};
  const auto build = [&](neighbors::CellGrid<Dim>& grid, neighbors::NeighborList& nl,
                         const Step& st, const neighbors::CanonicalOrder<Dim>* o) {
    std::vector<Vec<Dim>> xs(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(st.count));
    std::vector<double> hs(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(st.count));
    std::vector<Tensor<Dim>> Hs(H.begin(), H.begin() + static_cast<std::ptrdiff_t>(st.count));
    for (std::size_t i = 0; i < st.count; ++i) {
      const double s = x[i][0] < 0.5 ? st.lowerScale : st.scale;
      hs[i] *= s, Hs[i] /= s;
    }
    const neighbors::CanonicalOrder<Dim> part{std::span<const ParticleId>(id).first(st.count), xs};
    const auto* po = o ? &part : nullptr;
    if (ellipsoids)
      neighbors::buildNeighborList<Dim>(xs, hs, std::span<const Tensor<Dim>>(Hs), st.ownedRows, 2.0,
                                        grid, nl, po);
    else
      neighbors::buildNeighborList<Dim>(xs, hs, st.ownedRows, 2.0, grid, nl, po);
  };
  const auto builds = [&](int threads, const neighbors::CanonicalOrder<Dim>* o) {
    const int before = threadCount();
    setThreadCount(threads);
    setThreadedRows(1); // these few thousand rows in threads too
    neighbors::CellGrid<Dim> grid;
    neighbors::NeighborList nl;
    std::vector<neighbors::NeighborList> lists;
    for (const Step& st : steps) {
      build(grid, nl, st, o);
      lists.push_back(nl);
      // Each against a first build of the same particles (the one-thread pass, no regions).
      neighbors::CellGrid<Dim> freshGrid;
      neighbors::NeighborList fresh;
      build(freshGrid, fresh, st, o);
      EXPECT_EQ(fresh.offsets, nl.offsets) << threads << " threads, step " << lists.size();
      EXPECT_EQ(fresh.units, nl.units) << threads << " threads, step " << lists.size();
      EXPECT_EQ(fresh.base, nl.base) << threads << " threads, step " << lists.size();
    }
    setThreadCount(before);
    setThreadedRows(4096);
    return lists;
  };
  for (const auto* o : {&order, static_cast<const neighbors::CanonicalOrder<Dim>*>(nullptr)}) {
    const auto one = builds(1, o);
    ASSERT_GT(one[0].pairs(), 10 * owned);
    ASSERT_GT(one[2].pairs(), one[1].pairs() + one[1].pairs() / 5); // past the regions' margin
    for (int threads : {2, 3, 7}) {
      const auto many = builds(threads, o);
      for (std::size_t b = 0; b < one.size(); ++b) {
        EXPECT_EQ(many[b].offsets, one[b].offsets) << threads << " threads, build " << b;
        EXPECT_EQ(many[b].units, one[b].units) << threads << " threads, build " << b;
        EXPECT_EQ(many[b].base, one[b].base) << threads << " threads, build " << b;
      }
    }
  }
}
} // namespace

TEST(NeighborList, SameListsOnAnyThreadCount) {
  compareThreadCounts<2>(false);
  compareThreadCounts<3>(false);
  compareThreadCounts<3>(true);
}
