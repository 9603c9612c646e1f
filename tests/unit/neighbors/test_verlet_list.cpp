// Kept neighbor lists (VerletList.hpp): while the skin's bound says the wide list holds, its
// filtered rows equal a fresh search's, entry for entry (set and canonical order), for spheres
// and ellipsoids, with particles moved and supports grown, shrunk and turned; the bound is
// not vacuous (a move past it is reported); the row sort agrees with std::sort.
#include "spall/neighbors/VerletList.hpp"

#include "spall/core/SymmetricEigen.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <numeric>
#include <random>

using namespace spall;

namespace {

template <int Dim> Tensor<Dim> rotation(double angle) {
  Tensor<Dim> R = Tensor<Dim>::Identity();
  if constexpr (Dim >= 2) {
    R(0, 0) = std::cos(angle), R(0, 1) = -std::sin(angle);
    R(1, 0) = std::sin(angle), R(1, 1) = std::cos(angle);
  }
  return R;
}

template <int Dim> struct Cloud {
  std::vector<Vec<Dim>> x;
  std::vector<double> h;
  std::vector<Tensor<Dim>> H; // empty for spheres
  std::vector<ParticleId> id;
};

template <int Dim> Cloud<Dim> makeCloud(std::size_t n, bool ellipsoids, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0), hd(0.03, 0.07), turn(0.0, 3.14159);
  Cloud<Dim> c;
  c.x.resize(n), c.h.resize(n), c.id.resize(n);
  if (ellipsoids) c.H.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) c.x[i][d] = u(rng);
    c.id[i] = static_cast<ParticleId>((i * 7919) % n); // rows not in id order
    if (!ellipsoids) {
      c.h[i] = hd(rng);
      continue;
    }
    Vec<Dim> axes;
    for (int d = 0; d < Dim; ++d) axes[d] = hd(rng);
    const Tensor<Dim> R = rotation<Dim>(turn(rng));
    c.H[i] = R * axes.cwiseInverse().asDiagonal() * R.transpose();
    c.h[i] = axes.maxCoeff();
  }
  return c;
}

// A search with rows in the canonical order (its places into `places` if given), or in the
// search's own order (`ordered` false).
template <int Dim>
void search(const Cloud<Dim>& c, std::size_t owned, double support, neighbors::NeighborList& out,
            std::vector<std::uint32_t>* places = nullptr, bool ordered = true) {
  neighbors::CellGrid<Dim> grid;
  const neighbors::CanonicalOrder<Dim> order{c.id, c.x, places};
  const auto* o = ordered ? &order : nullptr;
  if (c.H.empty())
    neighbors::buildNeighborList<Dim>(c.x, c.h, owned, support, grid, out, o);
  else
    neighbors::buildNeighborList<Dim>(c.x, c.h, std::span<const Tensor<Dim>>(c.H), owned, support,
                                      grid, out, o);
}

// The rows of a list as the loops see them (of(i)), sorted when `sorted`.
std::vector<std::vector<std::uint32_t>> rowsOf(const neighbors::NeighborList& nl, std::size_t owned,
                                               bool sorted = false) {
  std::vector<std::vector<std::uint32_t>> rows(owned);
  for (std::size_t i = 0; i < owned; ++i) {
    rows[i] = nl.row(i);
    if (sorted) std::sort(rows[i].begin(), rows[i].end());
  }
  return rows;
}

template <int Dim> std::span<const Tensor<Dim>> metrics(const Cloud<Dim>& c) {
  return std::span<const Tensor<Dim>>(c.H);
}

// Moves every particle by up to `move` of its support and scales its support by up to
// 1 +- `grow` (ellipsoids also turned a little), the same for owned and ghost rows.
template <int Dim>
void perturb(Cloud<Dim>& c, double support, double move, double grow, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < c.x.size(); ++i) {
    Vec<Dim> dir;
    for (int d = 0; d < Dim; ++d) dir[d] = u(rng);
    const double scale = 1.0 + grow * u(rng);
    if (c.H.empty()) {
      c.x[i] += move * support * c.h[i] * dir / std::sqrt(static_cast<double>(Dim));
      c.h[i] *= scale;
    } else {
      const double hmin = 1.0 / c.H[i].cwiseAbs().rowwise().sum().maxCoeff();
      c.x[i] += move * support * hmin * dir / std::sqrt(static_cast<double>(Dim));
      const Tensor<Dim> R = rotation<Dim>(0.02 * u(rng));
      c.H[i] = R * c.H[i] * R.transpose() / scale;
      c.h[i] = 1.0 / symmetricEigenvalues<Dim>(c.H[i]).minCoeff();
    }
  }
}

// The cloud's first `owned` particles own rows (the rest are ghosts). ordered: rows in the
// canonical order (else the search's own: rows compared as sets).
template <int Dim>
void keptListsMatchFreshSearches(Cloud<Dim> c, std::size_t owned, bool ordered,
                                 std::mt19937_64& rng) {
  const double support = 2.0, skin = 0.15;
  neighbors::VerletList<Dim> verlet(skin);
  search(c, owned, verlet.widened(support), verlet.wide(), &verlet.places(), ordered);
  verlet.record(c.x, c.h, metrics(c), owned);
  const Cloud<Dim> built = c;
  int held = 0;
  for (int step = 0; step < 12; ++step) {
    perturb(c, support, 0.004, 0.004, rng);
    const auto m =
        verlet.drift(std::span<const Vec<Dim>>(c.x).first(owned), c.h, metrics(c), support);
    // (The ghosts moved as the owned rows did: the maxima over owned rows cover them here, as
    // the maxima over all ranks do in a run.)
    if (!verlet.holds(m)) break;
    ++held;
    // (Filtered in place step after step: rows where pairs came or left are rewritten.)
    neighbors::NeighborList fresh;
    verlet.filter(c.x, c.h, metrics(c), support);
    search(c, owned, support, fresh, nullptr, ordered);
    ASSERT_GT(fresh.pairs(), 10 * owned);
    EXPECT_EQ(verlet.wide().pairs(), fresh.pairs()) << "step " << step;
    EXPECT_TRUE(rowsOf(verlet.wide(), owned, !ordered) == rowsOf(fresh, owned, !ordered))
        << "step " << step;
  }
  // Small moves: the wide list held for several steps (else nothing above was tested).
  EXPECT_GE(held, 4);
  // One particle moved by more than the skin's share: the bound must say so.
  c = built;
  c.x[7][0] += 0.6 * skin * support * c.h[7];
  EXPECT_FALSE(verlet.holds(
      verlet.drift(std::span<const Vec<Dim>>(c.x).first(owned), c.h, metrics(c), support)));
  // A support grown by more than the skin: likewise.
  c = built;
  c.h[11] *= 1.0 + 1.2 * skin;
  if (!c.H.empty()) c.H[11] /= 1.0 + 1.2 * skin;
  EXPECT_FALSE(verlet.holds(
      verlet.drift(std::span<const Vec<Dim>>(c.x).first(owned), c.h, metrics(c), support)));
}

template <int Dim> void keptListsMatchFreshSearches(bool ellipsoids, bool ordered = true) {
  std::mt19937_64 rng(5);
  keptListsMatchFreshSearches<Dim>(makeCloud<Dim>(2500, ellipsoids, rng), 2000, ordered, rng);
}

} // namespace

// Rows whose neighbors lie more than 65536 places apart in the local order are stored wide (32
// bits a neighbor), the others narrow (16 bits from the row's smallest index): 170000 particles
// on a line, the first 70000 in index order along its first half (narrow rows), the rest at
// random along the second (mostly wide rows; pairs found from the other side turn narrow rows at
// the seam wide). Kept and filtered rows still equal fresh searches, entry for entry.
TEST(VerletList, KeptListsMatchFreshSearchesWithWideRows) {
  const std::size_t n = 170000, owned = 168000, ordered = 70000;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0), hd(2.0, 4.0);
  Cloud<1> c;
  c.x.resize(n), c.h.resize(n), c.id.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // (The halves at their own spacings: about 12 neighbors a row in both.)
    const double dx = 0.5 / static_cast<double>(i < ordered ? ordered : n - ordered);
    c.x[i][0] = i < ordered ? (static_cast<double>(i) + 0.5) * dx : 0.5 + 0.5 * u(rng);
    c.h[i] = hd(rng) * dx;
    c.id[i] = static_cast<ParticleId>((i * 7919) % n);
  }
  neighbors::NeighborList nl;
  search(c, owned, 2.0, nl);
  std::size_t wide = 0;
  for (std::size_t i = 0; i < owned; ++i) wide += nl.base[i] == neighbors::NeighborList::kWide;
  ASSERT_GT(wide, owned / 4);     // both kinds of row are tested
  ASSERT_LT(wide, 3 * owned / 4); // (about half of each)
  // The same units on any thread count (the rows' regions, spills and the merge of the pairs
  // found from the other side, which widens rows, all threaded).
  const int before = threadCount();
  for (int threads : {2, 3}) {
    setThreadCount(threads);
    setThreadedRows(1);
    neighbors::NeighborList many;
    search(c, owned, 2.0, many);
    EXPECT_EQ(many.offsets, nl.offsets) << threads << " threads";
    EXPECT_EQ(many.units, nl.units) << threads << " threads";
    EXPECT_EQ(many.base, nl.base) << threads << " threads";
  }
  setThreadCount(before);
  setThreadedRows(4096);
  keptListsMatchFreshSearches<1>(c, owned, true, rng);
}

// A row's encoding: narrow up to a span of 65535, wide beyond; either decodes to the row.
TEST(NeighborList, RowsDecodeToWhatWasAppended) {
  const std::vector<std::vector<std::uint32_t>> rows = {
      {}, {5}, {70000, 4465, 4465 + 17}, {65536, 0}, {4000000000u, 3, 77}, {9, 8, 7, 6}};
  neighbors::NeighborList nl;
  nl.offsets.push_back(0);
  std::size_t pairs = 0;
  for (const auto& r : rows) nl.append(r), pairs += r.size();
  const std::uint32_t kWide = neighbors::NeighborList::kWide;
  const std::vector<std::uint32_t> bases = {0, 5, 4465, kWide, kWide, 6};
  ASSERT_EQ(nl.rows(), rows.size());
  EXPECT_EQ(nl.base, bases);
  EXPECT_EQ(nl.pairs(), pairs);
  std::vector<std::uint32_t> buf;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(nl.row(i), rows[i]) << "row " << i;
    const auto got = nl.of(i, buf);
    EXPECT_EQ(std::vector<std::uint32_t>(got.begin(), got.end()), rows[i]) << "row " << i;
    const std::size_t units = nl.offsets[i + 1] - nl.offsets[i];
    EXPECT_EQ(units, (bases[i] == kWide ? 2 : 1) * rows[i].size()) << "row " << i;
  }
}

TEST(VerletList, KeptListsMatchFreshSearches2D) {
  keptListsMatchFreshSearches<2>(false);
}
TEST(VerletList, KeptListsMatchFreshSearches3D) {
  keptListsMatchFreshSearches<3>(false);
}
TEST(VerletList, KeptEllipsoidListsMatchFreshSearches2D) {
  keptListsMatchFreshSearches<2>(true);
}
TEST(VerletList, KeptEllipsoidListsMatchFreshSearches3D) {
  keptListsMatchFreshSearches<3>(true);
}

// The bound is not a formality: moves that use up the skin (a tenth of it left unused by the
// margins) leave pairs out of the wide list, which a fresh search then has.
TEST(VerletList, PairsAreMissedPastTheSkin) {
  const std::size_t n = 3000, owned = 3000;
  const double support = 2.0, skin = 0.1;
  std::mt19937_64 rng(9);
  Cloud<3> c = makeCloud<3>(n, false, rng);
  neighbors::VerletList<3> verlet(skin);
  search(c, owned, verlet.widened(support), verlet.wide(), &verlet.places());
  verlet.record(c.x, c.h, {}, owned);
  perturb(c, support, 0.2, 0.0, rng);
  EXPECT_FALSE(verlet.holds(verlet.drift(c.x, c.h, {}, support)));
  neighbors::NeighborList fresh;
  verlet.filter(c.x, c.h, {}, support);
  search(c, owned, support, fresh);
  EXPECT_LT(verlet.wide().pairs(), fresh.pairs());
}

// Rows in the search's own order (no canonical order asked for): the step's rows hold the pairs
// a fresh search finds, in some order, after pairs came into reach and left it.
TEST(VerletList, UnorderedKeptListsHoldFreshSearchesPairs) {
  keptListsMatchFreshSearches<3>(false, false);
}

// Rows are sorted by a bitmap of their span or radix passes over it (insertion below 24
// entries): against std::sort on short and long rows, narrow and wide spans (either side of
// the bitmap's limit, 64 (512 + n)), repeated values, and distinct ones (a row's places).
TEST(VerletList, RowSortAgreesWithStdSort) {
  std::mt19937_64 rng(3);
  for (std::size_t length : {0, 1, 5, 23, 24, 25, 118, 400}) {
    for (std::uint32_t span : {1u, 300u, 3700u, 70000u, 20000000u, 4294967295u}) {
      // Distinct values within the span (when it holds enough), in random order.
      if (span >= length && length > 0 && span < 100000u) {
        std::vector<std::uint32_t> all(span + 1u);
        std::iota(all.begin(), all.end(), 7u);
        std::shuffle(all.begin(), all.end(), rng);
        std::vector<std::uint32_t> row(all.begin(), all.begin() + static_cast<long>(length));
        std::vector<std::uint32_t> tmp(length), expect = row;
        std::sort(expect.begin(), expect.end());
        neighbors::sortRow(row.data(), row.data() + row.size(), tmp.data());
        EXPECT_EQ(row, expect) << length << " distinct entries over " << span;
      }
      std::uniform_int_distribution<std::uint32_t> u(0, span);
      std::vector<std::uint32_t> row(length), tmp(length), expect;
      for (auto& v : row) v = u(rng) + (span < 1000u ? 123456u : 0u);
      expect = row;
      std::sort(expect.begin(), expect.end());
      neighbors::sortRow(row.data(), row.data() + row.size(), tmp.data());
      EXPECT_EQ(row, expect) << length << " entries over " << span;
    }
  }
}
