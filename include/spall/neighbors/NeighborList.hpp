#pragma once
// Neighbor search over owned + ghost particles with a uniform cell grid (linked cells via a
// counting sort). A pair (i, j) is kept when r_ij < support * max(h_i, h_j), or for ellipsoidal
// supports (ASPH) when either support covers the other particle: the symmetrised
// (gather-scatter) interaction of the SPH equations needs both sides' supports. Lists are built
// for owned particles only, in compressed rows of 16-bit offsets where a row's neighbors are
// close in the local order, else 32-bit indices (memory: ~2 bytes per pair; NeighborList below).
#include "spall/core/MemoryAccounting.hpp"
#include "spall/core/Threads.hpp"
#include "spall/core/Types.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace spall::neighbors {

// Rows of neighbor indices, compressed: row i is the units [offsets[i], offsets[i+1]) of `units`.
// The local order follows the space-filling curve, so most rows' neighbors lie within 65536
// places of each other: such a narrow row holds each j in one 16-bit unit, j - base[i] (base:
// the row's smallest j). A row spanning more (ghosts, which follow all owned particles; far
// parts of a long curve) is wide: each j in two units, low half first, and base[i] = kWide.
// sedov_3d: 95% of rows narrow with 97k particles on a rank, 88% with 405k; the lists' memory
// falls from 4 to ~2.1 bytes per pair. Loops read a row decoded into a buffer of their own (of).
struct NeighborList {
  static constexpr std::uint32_t kWide = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint64_t> offsets; // owned count + 1, in units
  std::vector<std::uint16_t> units;
  std::vector<std::uint32_t> base; // per row
  // A kept list's rows (VerletList.hpp) hold more than the step's pairs: row i is then the
  // first counts[i] entries of its row, and keptPairs their total. Empty for a search's rows.
  std::vector<std::uint32_t> counts;
  std::uint64_t entries = 0; // the whole rows' pairs
  std::uint64_t keptPairs = 0;

  std::size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t pairs() const { return counts.empty() ? entries : keptPairs; }
  // Row i's whole length (a kept list's: the step's pairs and those beyond).
  std::size_t length(std::size_t i) const {
    const std::size_t u = offsets[i + 1] - offsets[i];
    return base[i] == kWide ? u / 2 : u;
  }
  // The step's pairs of row i.
  std::size_t count(std::size_t i) const { return counts.empty() ? length(i) : counts[i]; }
  // The first n entries of row i, into `to`.
  void decode(std::size_t i, std::size_t n, std::uint32_t* to) const {
    const std::uint16_t* u = units.data() + offsets[i];
    const std::uint32_t b = base[i];
    if (b != kWide)
      for (std::size_t k = 0; k < n; ++k) to[k] = b + u[k];
    else
      for (std::size_t k = 0; k < n; ++k)
        to[k] = u[2 * k] | static_cast<std::uint32_t>(u[2 * k + 1]) << 16;
  }
  // The smallest and largest index of row i's whole length ({max, 0} for an empty row).
  std::pair<std::uint32_t, std::uint32_t> bounds(std::size_t i) const {
    const std::uint16_t* u = units.data() + offsets[i];
    const std::size_t n = length(i);
    if (n == 0) return {std::numeric_limits<std::uint32_t>::max(), 0};
    if (base[i] != kWide) // (the base is the row's smallest index)
      return {base[i], base[i] + *std::max_element(u, u + n)};
    std::uint32_t lo = std::numeric_limits<std::uint32_t>::max(), hi = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t j = u[2 * k] | static_cast<std::uint32_t>(u[2 * k + 1]) << 16;
      lo = std::min(lo, j), hi = std::max(hi, j);
    }
    return {lo, hi};
  }
  // Row i (a kept list's: the step's pairs), decoded into `buf`, which grows as needed.
  std::span<const std::uint32_t> of(std::size_t i, std::vector<std::uint32_t>& buf) const {
    const std::size_t n = count(i);
    if (buf.size() < n) buf.resize(n + n / 2);
    decode(i, n, buf.data());
    return {buf.data(), n};
  }
  // A copy of row i (the step's pairs), where a loop is not hot.
  std::vector<std::uint32_t> row(std::size_t i) const {
    std::vector<std::uint32_t> r(count(i));
    decode(i, r.size(), r.data());
    return r;
  }
  // Encoding: the base of a row of n indices (kWide where they span more than 16 bits), the
  // units it takes, and the units themselves.
  static std::uint32_t baseOf(const std::uint32_t* row, std::size_t n) {
    if (n == 0) return 0;
    std::uint32_t lo = row[0], hi = row[0];
    for (std::size_t k = 1; k < n; ++k) lo = std::min(lo, row[k]), hi = std::max(hi, row[k]);
    return baseOf(lo, hi);
  }
  // (From the row's smallest and largest index.)
  static std::uint32_t baseOf(std::uint32_t lo, std::uint32_t hi) {
    return hi - lo <= 0xffffu ? lo : kWide;
  }
  static std::size_t unitsOf(std::uint32_t b, std::size_t n) { return b == kWide ? 2 * n : n; }
  static void encode(const std::uint32_t* row, std::size_t n, std::uint32_t b, std::uint16_t* to) {
    if (b != kWide)
      for (std::size_t k = 0; k < n; ++k) to[k] = static_cast<std::uint16_t>(row[k] - b);
    else
      for (std::size_t k = 0; k < n; ++k) {
        to[2 * k] = static_cast<std::uint16_t>(row[k]);
        to[2 * k + 1] = static_cast<std::uint16_t>(row[k] >> 16);
      }
  }
  // Row i rewritten in place: the same neighbors (so the same base and units), another order.
  void rewrite(std::size_t i, const std::uint32_t* row) {
    encode(row, length(i), base[i], units.data() + offsets[i]);
  }
  // Appends a row (a list built row by row: offsets starts as {0}).
  void append(std::span<const std::uint32_t> row) {
    const std::uint32_t b = baseOf(row.data(), row.size());
    const std::size_t at = units.size();
    units.resize(at + unitsOf(b, row.size()));
    encode(row.data(), row.size(), b, units.data() + at);
    base.push_back(b);
    offsets.push_back(units.size());
    entries += row.size();
  }
  std::size_t bytes() const { return allocatedBytes(offsets, units, base, counts); }
};

// A rank-count-independent order of particles: ids, then positions to tell a particle's periodic
// and mirror images apart. Every row is sorted by it, so the neighbor sums are added in the same
// order on any decomposition (a run is bit-for-bit identical on any number of ranks), and a row
// is the same sequence whichever wider list it was filtered from (neighbors/VerletList.hpp).
template <int Dim> struct CanonicalOrder {
  std::span<const ParticleId> id;
  std::span<const Vec<Dim>> x;
  std::vector<std::uint32_t>* places = nullptr; // if set, receives each particle's place
  bool less(std::uint32_t a, std::uint32_t b) const {
    if (id[a] != id[b]) return id[a] < id[b];
    for (int d = 0; d < Dim; ++d)
      if (x[a][d] != x[b][d]) return x[a][d] < x[b][d];
    return false; // the same image twice: identical values, either order gives the same sums
  }
};

template <int Dim> class CellGrid {
public:
  // Bins all `x` (owned and ghosts) into cells of `cellSize` aligned to the origin. The grid is
  // coarsened when the particles' extent would need more than ~2 cells per particle (a far-flung
  // particle must not cost memory). The members' positions (and `radius`, if given) are copied
  // in member order, so that a search streams through contiguous memory instead of gathering
  // every candidate from the store.
  void build(std::span<const Vec<Dim>> x, double cellSize, std::span<const double> radius = {}) {
    Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::max());
    Vec<Dim> hi = Vec<Dim>::Constant(std::numeric_limits<double>::lowest());
    for (const auto& p : x) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if (x.empty()) lo.setZero(), hi.setZero();
    double size = cellSize;
    const double maxCells = 2.0 * static_cast<double>(x.size()) + 64.0;
    for (;;) {
      double total = 1.0;
      for (int d = 0; d < Dim; ++d) {
        base_[d] = static_cast<std::int64_t>(std::floor(lo[d] / size));
        n_[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(hi[d] / size)) -
                                              base_[d] + 1);
        total *= static_cast<double>(n_[d]);
      }
      if (total <= maxCells) break;
      size *= std::pow(total / maxCells, 1.0 / Dim) * 1.01;
    }
    size_ = size;
    inv_ = 1.0 / size;
    std::int64_t cells = 1;
    for (int d = 0; d < Dim; ++d) cells *= n_[d];
    start_.assign(static_cast<std::size_t>(cells) + 1, 0);
    cellOf_.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      cellOf_[i] = cellIndex(x[i]);
      ++start_[cellOf_[i] + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    members_.resize(x.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < x.size(); ++i)
      members_[fill[cellOf_[i]]++] = static_cast<std::uint32_t>(i);
    xs_.resize(x.size());
    for (std::size_t m = 0; m < x.size(); ++m) xs_[m] = x[members_[m]];
    rs_.resize(radius.size());
    for (std::size_t m = 0; m < radius.size(); ++m) rs_[m] = radius[members_[m]];
  }

  double cellSize() const { return size_; }

  std::uint32_t cellIndex(const Vec<Dim>& p) const {
    std::int64_t c = 0;
    for (int d = Dim - 1; d >= 0; --d) {
      std::int64_t k = static_cast<std::int64_t>(std::floor(p[d] * inv_)) - base_[d];
      k = std::clamp<std::int64_t>(k, 0, n_[d] - 1);
      c = c * n_[d] + k;
    }
    return static_cast<std::uint32_t>(c);
  }
  std::span<const std::uint32_t> cellOf() const { return cellOf_; }

  // Member m (a position in the cell-sorted order) is particle members()[m] at sortedX()[m].
  std::span<const std::uint32_t> members() const { return members_; }
  std::span<const Vec<Dim>> sortedX() const { return xs_; }
  std::span<const double> sortedRadius() const { return rs_; }

  // Calls visit(j) for every particle in the cells within `reach` cells of cell `c` along each
  // axis (a (2 reach + 1)^Dim block), cells in z, y, x order.
  template <class F> void forEachNear(std::uint32_t c, std::int64_t reach, F&& visit) const {
    forEachRangeNear(c, reach, [&](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t m = b; m < e; ++m) visit(members_[m]);
    });
  }

  // The same block as contiguous ranges [b, e) of member positions, one per row of cells.
  template <class F> void forEachRangeNear(std::uint32_t c, std::int64_t reach, F&& range) const {
    forEachRangeNear(c, std::array<std::int64_t, 3>{reach, reach, reach}, range);
  }
  // A block of (2 reach[d] + 1) cells along each axis d (an ellipsoid's bounding box).
  template <class F>
  void forEachRangeNear(std::uint32_t c, const std::array<std::int64_t, 3>& reach,
                        F&& range) const {
    std::int64_t k[3] = {0, 0, 0};
    std::int64_t rem = c;
    for (int d = 0; d < Dim; ++d) {
      k[d] = rem % n_[d];
      rem /= n_[d];
    }
    const std::int64_t r1 = Dim >= 2 ? reach[1] : 0, r2 = Dim >= 3 ? reach[2] : 0;
    const std::int64_t x0 = std::max<std::int64_t>(k[0] - reach[0], 0);
    const std::int64_t x1 = std::min<std::int64_t>(k[0] + reach[0], n_[0] - 1);
    for (std::int64_t z = std::max<std::int64_t>(k[2] - r2, 0);
         z <= std::min<std::int64_t>(k[2] + r2, n_[2] - 1); ++z) {
      for (std::int64_t y = std::max<std::int64_t>(k[1] - r1, 0);
           y <= std::min<std::int64_t>(k[1] + r1, n_[1] - 1); ++y) {
        const std::int64_t base = (z * n_[1] + y) * n_[0];
        // The cells x0..x1 of one row are contiguous in `members_`.
        range(start_[static_cast<std::size_t>(base + x0)],
              start_[static_cast<std::size_t>(base + x1 + 1)]);
      }
    }
  }

  std::size_t bytes() const { return allocatedBytes(start_, cellOf_, members_, xs_, rs_); }

private:
  double size_ = 1.0, inv_ = 1.0;
  std::int64_t base_[3] = {0, 0, 0};
  std::int64_t n_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> cellOf_;
  std::vector<std::uint32_t> members_;
  std::vector<Vec<Dim>> xs_;
  std::vector<double> rs_;
};

// Builds the neighbor lists of the first `owned` particles of x (the rest are ghosts): every j
// with r_ij < support * max(h_i, h_j) (spheres; the ellipsoidal variant below). Each particle
// gathers within its own support; a pair that only the larger support reaches is found from that
// side and added to the other's list. The grid is sized by the local median h, so that a few
// particles with a large h (free surfaces, a blast's hot core) do not coarsen the search for
// all. With `order` every row is sorted by it (rank-count-independent sums); without, a row
// holds its own gathers in cell order, then the pairs found from the other side.
template <int Dim> void sortRows(NeighborList& nl, const CanonicalOrder<Dim>& order, std::size_t n);

namespace detail {
// A chunk of consecutive rows of a search: its rows go into its region of the list (units),
// sized from the last build's rows in the same places; what does not fit spills into a vector of
// its own (joined in place by joinChunks). It also keeps the pairs it found from the other side.
struct ListChunk {
  std::uint64_t start = 0, capacity = 0, used = 0, entries = 0;
  std::uint16_t* region = nullptr;
  std::vector<std::uint16_t> spill;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> extra; // (owned i, j reaching i)
  // Encodes a row; returns its base. (Once a row has spilled, all that follow it do: the rows
  // stay in order.)
  std::uint32_t append(const std::uint32_t* row, std::size_t length, std::uint32_t lo,
                       std::uint32_t hi) {
    const std::uint32_t b = length > 0 ? NeighborList::baseOf(lo, hi) : 0;
    const std::size_t u = NeighborList::unitsOf(b, length);
    entries += length;
    if (spill.empty() && used + u <= capacity) {
      NeighborList::encode(row, length, b, region + used);
      used += u;
    } else {
      const std::size_t at = spill.size();
      spill.resize(at + u);
      NeighborList::encode(row, length, b, spill.data() + at);
    }
    return b;
  }
  std::size_t size() const { return used + spill.size(); }
};
using OtherSide = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

// The square of an inscribed sphere's radius of an ellipsoidal support, support / |H|_inf
// (|H|_inf, the largest absolute row sum, bounds the largest eigenvalue): inside it a particle is
// covered without evaluating the quadratic form, which then remains for the thin shell between
// the spheres. (Both sides of a pair evaluate it with the same expressions, so they agree bit for
// bit.)
template <int Dim> double innerRadius2(const Tensor<Dim>& Hm, double support) {
  const double rin = support / Hm.cwiseAbs().rowwise().sum().maxCoeff();
  return rin * rin;
}

// The gathers of particles [aBegin, aEnd) on the grid: each particle's row (owned ones), and
// the pairs only the other side reaches (ListChunk::extra).
template <int Dim, bool Ellipsoidal> struct ChunkSearch {
  std::span<const Vec<Dim>> x;
  std::span<const Tensor<Dim>> H;
  std::size_t owned;
  double support;
  const CellGrid<Dim>& grid;
  const std::vector<double>& radius;
  // Ellipsoidal supports: the metric G = H^T H of every particle (|H x|^2 = x . G x) and the
  // inscribed spheres' squared radii, in member order for the scatter test.
  const std::vector<Tensor<Dim>>& Gs;
  const std::vector<double>& inner2s;
  NeighborList& out;

  void operator()(std::size_t aBegin, std::size_t aEnd, ListChunk& chunk) const {
    std::vector<std::uint32_t> hit, row; // member positions within reach; a's row
    std::vector<double> hitR2;
    for (std::size_t a = aBegin; a < aEnd; ++a) {
      const std::size_t found = candidates(a, hit, hitR2);
      if (row.size() < found) row.resize(hit.size());
      std::size_t length = 0;
      std::uint32_t lo = std::numeric_limits<std::uint32_t>::max(), hi = 0; // the row's span
      const auto members = grid.members();
      for (std::size_t k = 0; k < found; ++k) {
        const std::uint32_t m = hit[k], b = members[m];
        if (b == a) continue;
        row[length++] = b;
        lo = std::min(lo, b), hi = std::max(hi, b);
        if (b < owned && !reachesBack(a, m, hitR2[k]))
          chunk.extra.emplace_back(b, static_cast<std::uint32_t>(a));
      }
      // The row, appended whole; its end relative to the chunk's first row (made absolute when
      // joined).
      if (a < owned) {
        out.base[a] = chunk.append(row.data(), length, lo, hi);
        out.offsets[a + 1] = chunk.size();
      }
    }
  }

  // The member positions within a's support, and their squared distances: the first `found`
  // entries of hit and hitR2.
  std::size_t candidates(std::size_t a, std::vector<std::uint32_t>& hit,
                         std::vector<double>& hitR2) const {
    const Vec<Dim> xa = x[a];
    const double cell = grid.cellSize();
    const auto xs = grid.sortedX();
    // (For ellipsoids the sphere is only a first cut, a little wider so that the ellipsoid
    // test alone decides: h and H agree to rounding only.)
    const double ra = radius[a], ra2 = ra * ra * (Ellipsoidal ? 1.0 + 1e-9 : 1.0);
    std::array<std::int64_t, 3> reach{0, 0, 0};
    [[maybe_unused]] Tensor<Dim> Ga;
    if constexpr (Ellipsoidal) {
      // The half-widths of the support's bounding box, support sqrt((G^-1)_dd), set the block
      // of cells searched.
      Ga = H[a].transpose() * H[a];
      const Tensor<Dim> Ginv = Ga.inverse();
      // (A broken H, non-finite, searches the whole grid and finds nothing: the run's
      // finiteness check reports the particle.)
      for (int d = 0; d < Dim; ++d) {
        const double cells = std::ceil(support * std::sqrt(Ginv(d, d)) / cell);
        reach[d] = cells < 1e9 ? static_cast<std::int64_t>(cells) : std::int64_t{1000000000};
      }
    } else {
      reach.fill(static_cast<std::int64_t>(std::ceil(ra / cell)));
    }
    // Branch-free compaction of the candidates within reach (about a quarter of the block in
    // 3D, so a taken/not-taken branch per candidate would mispredict often).
    std::size_t found = 0;
    grid.forEachRangeNear(grid.cellOf()[a], reach, [&](std::uint32_t b, std::uint32_t e) {
      if (hit.size() < found + (e - b)) hit.resize(2 * (found + (e - b))), hitR2.resize(hit.size());
      for (std::uint32_t m = b; m < e; ++m) {
        const Vec<Dim> d = xa - xs[m];
        hit[found] = m;
        const double r2 = d.squaredNorm();
        hitR2[found] = r2;
        found += r2 < ra2;
      }
    });
    if constexpr (Ellipsoidal) {
      // The enclosing sphere above (radius: the longest axis) was the cheap first cut; now the
      // ellipsoid itself, on the few that passed.
      const double inner2 = innerRadius2<Dim>(H[a], support), support2 = support * support;
      std::size_t kept = 0;
      for (std::size_t k = 0; k < found; ++k) {
        const std::uint32_t m = hit[k];
        bool in = hitR2[k] < inner2;
        if (!in) {
          const Vec<Dim> d = xa - xs[m];
          in = d.dot(Ga * d) < support2;
        }
        hit[kept] = m;
        hitR2[kept] = hitR2[k];
        kept += in;
      }
      found = kept;
    }
    return found;
  }

  // Whether member m (at squared distance r2 from a) reaches a itself; if not, its row gets a
  // from this side. (For ellipsoids the test is m's gather test evaluated again here; should
  // rounding ever decide a pair at exactly |H x| = support differently from the two sides, the
  // pair sits where W and W' vanish.)
  bool reachesBack(std::size_t a, std::uint32_t m, double r2) const {
    const auto rs = grid.sortedRadius();
    if constexpr (Ellipsoidal) {
      if (r2 < inner2s[m]) return true;
      if (r2 >= rs[m] * rs[m] * (1.0 + 1e-9)) return false; // outside m's enclosing sphere
      const Vec<Dim> d = x[a] - grid.sortedX()[m];
      return d.dot(Gs[m] * d) < support * support;
    } else {
      return r2 < rs[m] * rs[m];
    }
  }
};

// The first build has no rows to size the regions by: every stride-th row, searched alone,
// gives the mean row, and the regions are sized by it (what does not fit spills). A list grown
// as a vector would hold up to twice its size while it grows (sedov_3d: 40% of the run's peak
// memory).
template <class Search>
void estimateFirstRows(const Search& search, std::size_t owned,
                       std::vector<std::uint64_t>& previous) {
  const std::size_t stride = std::max<std::size_t>(1, owned / 512);
  ListChunk probe;
  std::size_t sampled = 0;
  for (std::size_t a = 0; a < owned; a += stride, ++sampled) search(a, a + 1, probe);
  const double mean = static_cast<double>(probe.size()) / static_cast<double>(sampled);
  previous.resize(owned + 1);
  for (std::size_t a = 0; a <= owned; ++a)
    previous[a] = static_cast<std::uint64_t>(mean * static_cast<double>(a));
}

// Each chunk's region of the list, sized from the last build's rows (`previous`) in the same
// places; the list reserved for them all.
inline void placeRegions(std::vector<ListChunk>& parts, const std::vector<std::uint64_t>& previous,
                         std::size_t n, std::size_t owned, NeighborList& out) {
  const std::size_t chunks = parts.size();
  const std::size_t before = previous.size() - 1; // last build's owned rows
  const double perRow = static_cast<double>(previous.back()) / static_cast<double>(before);
  std::uint64_t total = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t b = std::min(chunkBegin(n, chunks, c), owned);
    const std::size_t e = std::min(chunkBegin(n, chunks, c + 1), owned);
    const std::size_t bb = std::min(b, before), eb = std::min(e, before);
    const double estimate = static_cast<double>(previous[eb] - previous[bb]) +
                            perRow * static_cast<double>(e - b - (eb - bb));
    parts[c].start = total;
    parts[c].capacity = static_cast<std::uint64_t>(1.03 * estimate) + 64 * (e > b);
    total += parts[c].capacity;
  }
  // Room to grow by a fifth (reserved, not touched) before the list moves: spills are joined in
  // place up to it.
  if (out.units.capacity() < total) {
    std::vector<std::uint16_t>().swap(out.units);
    out.units.reserve(total + total / 5);
  }
  out.units.resize(total); // (only what lies past the last build's pairs is written here)
  for (auto& part : parts) part.region = out.units.data() + part.start;
}

// Join in place: chunk c's rows (its region, then its spill) go to base[c], right after the chunk
// before. Chunks that move up are placed first, the last first, then those that move down, the
// first first: no chunk's destination then covers rows not yet moved (each destination ends
// where the next chunk's begins, and a chunk moving down begins at or below its region).
// Memory: the list once, grown only by what all chunks spilled in all. Returns the chunks' pairs
// found from the other side, in order.
inline OtherSide joinChunks(std::vector<ListChunk>& parts, std::size_t n, std::size_t owned,
                            NeighborList& out) {
  const std::size_t chunks = parts.size();
  std::vector<std::uint64_t> base(chunks + 1, 0);
  std::size_t extras = 0;
  out.entries = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    base[c + 1] = base[c] + parts[c].size();
    extras += parts[c].extra.size();
    out.entries += parts[c].entries;
  }
  if (base[chunks] > out.units.size()) resizeWithHeadroom(out.units, base[chunks]);
  std::uint16_t* list = out.units.data();
  const auto place = [&](std::size_t c) {
    std::memmove(list + base[c], list + parts[c].start, parts[c].used * sizeof(std::uint16_t));
    std::copy(parts[c].spill.begin(), parts[c].spill.end(), list + base[c] + parts[c].used);
  };
  for (std::size_t c = chunks; c-- > 0;)
    if (base[c] > parts[c].start) place(c);
  for (std::size_t c = 0; c < chunks; ++c)
    if (base[c] <= parts[c].start) place(c);
  out.units.resize(base[chunks]);
#pragma omp parallel for schedule(static) if (threaded(n))
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t b = std::min(chunkBegin(n, chunks, c), owned);
    const std::size_t e = std::min(chunkBegin(n, chunks, c + 1), owned);
    for (std::size_t a = b; a < e; ++a) out.offsets[a + 1] += base[c];
  }
  OtherSide extra;
  extra.reserve(extras);
  for (std::size_t c = 0; c < chunks; ++c)
    extra.insert(extra.end(), parts[c].extra.begin(), parts[c].extra.end());
  return extra;
}

// The pairs found from the other side, merged into their owned rows: grouped by their owned
// particle with a counting sort (they were found in increasing j, so each group is already
// sorted by j), then merged in place, each row's own gathers first, then its group. A row that
// gains pairs may need more units (more pairs; a wider span): first each row's new base and
// units, then rows moved back to front to their places (a row's new place is never before its
// old one: no row grows shorter).
inline void mergeOtherSide(NeighborList& out, std::size_t owned, const OtherSide& extra) {
  std::vector<std::uint32_t> groupStart(owned + 1, 0);
  for (const auto& [i, j] : extra) ++groupStart[i + 1];
  for (std::size_t i = 0; i < owned; ++i) groupStart[i + 1] += groupStart[i];
  std::vector<std::uint32_t> grouped(extra.size());
  {
    std::vector<std::uint32_t> fill(groupStart.begin(), groupStart.end() - 1);
    for (const auto& [i, j] : extra) grouped[fill[i]++] = j;
  }
  std::vector<std::uint64_t> at(owned + 1, 0);
  std::vector<std::uint32_t> newBase(out.base);
#pragma omp parallel for schedule(dynamic, 256) if (threaded(owned))
  for (std::size_t i = 0; i < owned; ++i) {
    const std::size_t length = out.length(i), more = groupStart[i + 1] - groupStart[i];
    if (more > 0) {
      auto [lo, hi] = out.bounds(i);
      for (std::uint32_t k = groupStart[i]; k < groupStart[i + 1]; ++k)
        lo = std::min(lo, grouped[k]), hi = std::max(hi, grouped[k]);
      newBase[i] = NeighborList::baseOf(lo, hi);
    }
    at[i + 1] = NeighborList::unitsOf(newBase[i], length + more);
  }
  for (std::size_t i = 0; i < owned; ++i) at[i + 1] += at[i];
  resizeWithHeadroom(out.units, at[owned]);
  std::vector<std::uint32_t> buf;
  for (std::size_t i = owned; i-- > 0 && at[i + 1] != out.offsets[i + 1];) {
    const std::size_t length = out.length(i), more = groupStart[i + 1] - groupStart[i];
    if (more == 0 && newBase[i] == out.base[i]) {
      std::memmove(out.units.data() + at[i], out.units.data() + out.offsets[i],
                   (out.offsets[i + 1] - out.offsets[i]) * sizeof(std::uint16_t));
      continue;
    }
    resizeWithHeadroom(buf, length + more);
    out.decode(i, length, buf.data());
    std::copy_n(grouped.data() + groupStart[i], more, buf.data() + length);
    NeighborList::encode(buf.data(), length + more, newBase[i], out.units.data() + at[i]);
  }
  out.offsets.swap(at);
  out.base.swap(newBase);
  out.entries += extra.size();
}

template <int Dim, bool Ellipsoidal>
void buildNeighborList(std::span<const Vec<Dim>> x, std::span<const double> h,
                       std::span<const Tensor<Dim>> H, std::size_t owned, double support,
                       CellGrid<Dim>& grid, NeighborList& out, const CanonicalOrder<Dim>* order) {
  const std::size_t n = x.size();
  double hRef = 1.0;
  if (n > 0) {
    std::vector<double> hs(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(n));
    std::nth_element(hs.begin(), hs.begin() + static_cast<std::ptrdiff_t>(hs.size() / 2), hs.end());
    if (hs[hs.size() / 2] > 0.0) hRef = hs[hs.size() / 2];
  }
  std::vector<double> radius(n);
  for (std::size_t a = 0; a < n; ++a) radius[a] = support * h[a];
  // Cells of half the typical support: a (5 cells)^Dim block covers it with fewer candidates
  // than (3 cells of a full support)^Dim.
  grid.build(x, 0.5 * support * hRef, radius);
  std::vector<Tensor<Dim>> Gs;
  std::vector<double> inner2s;
  if constexpr (Ellipsoidal) {
    const auto members = grid.members();
    Gs.resize(n);
    inner2s.resize(n);
    for (std::size_t m = 0; m < n; ++m) {
      const Tensor<Dim>& Hm = H[members[m]];
      Gs[m] = Hm.transpose() * Hm;
      inner2s[m] = innerRadius2<Dim>(Hm, support);
    }
  }
  // The last build's rows estimate each chunk's share below.
  std::vector<std::uint64_t> previous;
  previous.swap(out.offsets);
  out.counts.clear(); // whole rows, as searched
  out.offsets.assign(owned + 1, 0);
  out.base.assign(owned, 0);
  const ChunkSearch<Dim, Ellipsoidal> search{x, H, owned, support, grid, radius, Gs, inner2s, out};
  // The particles are searched in chunks of consecutive a, in parallel (core/Threads.hpp); each
  // chunk keeps its rows and its pairs found from the other side, and the chunks are then joined
  // in order: the lists come out as one sequential pass makes them, on any thread count.
  const int threads = threadCount();
  const std::size_t chunks =
      threads == 1 || !threaded(n) ? 1 : 32 * static_cast<std::size_t>(threads);
  OtherSide extra;
  if (owned > 0 && (previous.size() < 2 || previous.back() == 0))
    estimateFirstRows(search, owned, previous);
  // Without owned rows, all of it is one spill that becomes the list. Else rows go into
  // regions, on one thread too (a row goes into a region with one copy: faster than into a
  // growing vector).
  if (owned == 0) {
    ListChunk all;
    all.spill.swap(out.units);
    all.spill.clear();
    search(0, n, all);
    out.units.swap(all.spill);
    out.entries = all.entries;
    extra.swap(all.extra);
  } else {
    std::vector<ListChunk> parts(chunks);
    placeRegions(parts, previous, n, owned, out);
    // (An exception must not leave a parallel region: a failed allocation is carried out.)
    std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) if (threaded(n))
    for (std::size_t c = 0; c < chunks; ++c) {
      try {
        search(chunkBegin(n, chunks, c), chunkBegin(n, chunks, c + 1), parts[c]);
      } catch (...) {
#pragma omp critical(spall_neighbor_failure)
        if (!failure) failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
    extra = joinChunks(parts, n, owned, out);
  }
  if (!extra.empty()) mergeOtherSide(out, owned, extra);
  if (order) sortRows<Dim>(out, *order, n);
}

// Compiled once, in src/neighbors/NeighborList.cpp: its code (what the compiler inlines into the
// search) does not depend on the file that calls it.
#define SPALL_NEIGHBOR_SEARCH(PREFIX, D, E)                                                        \
  PREFIX template void buildNeighborList<D, E>(                                                    \
      std::span<const Vec<D>>, std::span<const double>, std::span<const Tensor<D>>, std::size_t,   \
      double, CellGrid<D>&, NeighborList&, const CanonicalOrder<D>*);
#define SPALL_NEIGHBOR_SEARCHES(PREFIX)                                                            \
  SPALL_NEIGHBOR_SEARCH(PREFIX, 1, false)                                                          \
  SPALL_NEIGHBOR_SEARCH(PREFIX, 2, false)                                                          \
  SPALL_NEIGHBOR_SEARCH(PREFIX, 3, false)                                                          \
  SPALL_NEIGHBOR_SEARCH(PREFIX, 1, true)                                                           \
  SPALL_NEIGHBOR_SEARCH(PREFIX, 2, true)                                                           \
  SPALL_NEIGHBOR_SEARCH(PREFIX, 3, true)
SPALL_NEIGHBOR_SEARCHES(extern)

} // namespace detail

template <int Dim>
void buildNeighborList(std::span<const Vec<Dim>> x, std::span<const double> h, std::size_t owned,
                       double support, CellGrid<Dim>& grid, NeighborList& out,
                       const CanonicalOrder<Dim>* order = nullptr) {
  detail::buildNeighborList<Dim, false>(x, h, {}, owned, support, grid, out, order);
}

// Ellipsoidal supports (ASPH): particle a reaches the points y with |H_a (y - x_a)| < support, and
// a pair is kept when either reaches the other. h is each particle's longest axis (1/smallest
// eigenvalue of H): it sizes the grid, while each search covers only the support's bounding box.
template <int Dim>
void buildNeighborList(std::span<const Vec<Dim>> x, std::span<const double> h,
                       std::span<const Tensor<Dim>> H, std::size_t owned, double support,
                       CellGrid<Dim>& grid, NeighborList& out,
                       const CanonicalOrder<Dim>* order = nullptr) {
  detail::buildNeighborList<Dim, true>(x, h, H, owned, support, grid, out, order);
}

// Sorts [b, e) ascending with `tmp` (as long) as scratch: short runs by insertion, longer ones
// by a bitmap of the span max - min where it is narrow, else by least-significant-digit radix
// passes of 8 bits over it (a row's places span a few layers of its neighborhood: no
// mispredicted branches, which make comparison sorts of such rows slow).
inline void sortRow(std::uint32_t* b, std::uint32_t* e, std::uint32_t* tmp) {
  const std::size_t n = static_cast<std::size_t>(e - b);
  if (n < 24) {
    for (std::uint32_t* p = b + 1; p < e; ++p) {
      const std::uint32_t v = *p;
      std::uint32_t* q = p;
      for (; q > b && q[-1] > v; --q) q[0] = q[-1];
      *q = v;
    }
    return;
  }
  std::uint32_t lo = *b, hi = *b;
  for (const std::uint32_t* p = b; p < e; ++p) lo = std::min(lo, *p), hi = std::max(hi, *p);
  // Where the span is narrow, a bitmap of it read back word by word sorts without the radix
  // passes' 256-entry prefix sums, where short rows spent most of their sort (noh_2d: sortRow
  // 14% of the step before, 5% after). Narrow: its words fewer than the radix passes' work
  // (2 x 256 and 2n a pass, 2 passes below a span of 65536). A row's places are distinct; a
  // repeated value (not a row's) falls through to the radix passes.
  if (hi - lo < 64 * (512 + n)) {
    thread_local std::vector<std::uint64_t> bits;
    const std::size_t words = (hi - lo) / 64 + 1;
    bits.assign(words, 0);
    std::uint64_t repeated = 0;
    for (const std::uint32_t* p = b; p < e; ++p) {
      const std::uint64_t bit = std::uint64_t{1} << ((*p - lo) & 63);
      std::uint64_t& word = bits[(*p - lo) >> 6];
      repeated |= word & bit;
      word |= bit;
    }
    if (!repeated) {
      std::uint32_t* to = b;
      for (std::size_t w = 0; w < words; ++w)
        for (std::uint64_t m = bits[w]; m != 0; m &= m - 1)
          *to++ = lo + static_cast<std::uint32_t>(64 * w + std::countr_zero(m));
      return;
    }
  }
  std::uint32_t* from = b;
  std::uint32_t* to = tmp;
  for (unsigned shift = 0; shift < 32 && ((hi - lo) >> shift) != 0; shift += 8) {
    std::uint32_t count[257] = {};
    for (const std::uint32_t* p = from; p < from + n; ++p) ++count[((*p - lo) >> shift & 255) + 1];
    for (int d = 0; d < 256; ++d) count[d + 1] += count[d];
    for (const std::uint32_t* p = from; p < from + n; ++p)
      to[count[(*p - lo) >> shift & 255]++] = *p;
    std::swap(from, to);
  }
  if (from != b) std::copy_n(from, n, b);
}

// Sorts every row of `nl` by `order` (over the n particles the rows index): each particle's
// place in the order once (one sort of all), then each row by those places, rows in parallel.
template <int Dim>
void sortRows(NeighborList& nl, const CanonicalOrder<Dim>& order, std::size_t n) {
  std::vector<std::uint32_t> byOrder(n), place(n);
  for (std::size_t a = 0; a < n; ++a) byOrder[a] = static_cast<std::uint32_t>(a);
  std::sort(byOrder.begin(), byOrder.end(),
            [&](std::uint32_t a, std::uint32_t b) { return order.less(a, b); });
  for (std::size_t k = 0; k < n; ++k) place[byOrder[k]] = static_cast<std::uint32_t>(k);
  const std::size_t rows = nl.rows();
#pragma omp parallel if (threaded(rows))
  {
    std::vector<std::uint32_t> row, tmp;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < rows; ++i) {
      const std::size_t length = nl.length(i);
      if (row.size() < length) row.resize(2 * length), tmp.resize(2 * length);
      std::uint32_t* b = row.data();
      std::uint32_t* e = b + length;
      nl.decode(i, length, b);
      for (std::uint32_t* p = b; p != e; ++p) *p = place[*p];
      sortRow(b, e, tmp.data());
      for (std::uint32_t* p = b; p != e; ++p) *p = byOrder[*p];
      nl.rewrite(i, b);
    }
  }
  if (order.places) order.places->swap(place);
}

} // namespace spall::neighbors
