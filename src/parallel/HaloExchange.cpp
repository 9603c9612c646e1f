#include "spall/parallel/HaloExchange.hpp"

#include "spall/parallel/Exchange.hpp"
#include "spall/parallel/RowExchange.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall::parallel {

template <int Dim>
HaloExchange<Dim>::HaloExchange(MPI_Comm comm, std::vector<PeriodicAxis> periodic)
    : comm_(comm), periodic_(std::move(periodic)) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

template <int Dim>
void HaloExchange<Dim>::describeDomains(std::span<const Vec<Dim>> x,
                                        std::span<const Vec<Dim>> reach,
                                        std::span<const double> radius) {
  constexpr int per = 3 * Dim + 1;
  std::vector<double> mine(static_cast<std::size_t>(kBoxes * per));
  const std::size_t n = x.size();
  const std::size_t chunk = (n + kBoxes - 1) / kBoxes;
  for (int b = 0; b < kBoxes; ++b) {
    Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::infinity());
    Vec<Dim> hi = -lo;
    Vec<Dim> r = Vec<Dim>::Zero();
    double rad = 0.0;
    const std::size_t begin = std::min(n, static_cast<std::size_t>(b) * chunk);
    const std::size_t end = std::min(n, begin + chunk);
    for (std::size_t i = begin; i < end; ++i) {
      if (!x[i].allFinite()) continue; // reported by the run's finiteness check, not here
      lo = lo.cwiseMin(x[i]);
      hi = hi.cwiseMax(x[i]);
      r = r.cwiseMax(reach[i]);
      rad = std::max(rad, radius[i]);
    }
    double* out = &mine[static_cast<std::size_t>(b * per)];
    for (int d = 0; d < Dim; ++d) out[d] = lo[d], out[Dim + d] = hi[d], out[2 * Dim + d] = r[d];
    out[3 * Dim] = rad;
  }
  std::vector<double> all(mine.size() * static_cast<std::size_t>(size_));
  MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(),
                static_cast<int>(mine.size()), MPI_DOUBLE, comm_);
  boxes_.assign(all.size() / per, Box{});
  rankBox_.assign(static_cast<std::size_t>(size_), Box{});
  for (std::size_t k = 0; k < boxes_.size(); ++k) {
    Box& b = boxes_[k];
    for (int d = 0; d < Dim; ++d)
      b.lo[d] = all[k * per + d], b.hi[d] = all[k * per + Dim + d],
      b.reach[d] = all[k * per + 2 * Dim + d];
    b.radius = all[k * per + 3 * Dim];
    Box& u = rankBox_[k / kBoxes];
    if (k % kBoxes == 0) u = b;
    u.lo = u.lo.cwiseMin(b.lo);
    u.hi = u.hi.cwiseMax(b.hi);
    u.reach = u.reach.cwiseMax(b.reach);
    u.radius = std::max(u.radius, b.radius);
  }
}

namespace {

template <int Dim> double distance2(const Vec<Dim>& p, const Vec<Dim>& lo, const Vec<Dim>& hi) {
  double d2 = 0.0;
  for (int d = 0; d < Dim; ++d) {
    const double e = std::max({lo[d] - p[d], 0.0, p[d] - hi[d]});
    d2 += e * e;
  }
  return d2;
}

// Per-axis reach (bounding boxes of ellipsoids): every axis' distance to the box within its
// reach. (A pair (i, j) with x_j in i's ellipsoid has |x_j - x_i|_d within i's half-width along
// every axis d, so x_j is within the box's largest half-widths of the box.)
template <int Dim>
bool withinPerAxis(const Vec<Dim>& p, const Vec<Dim>& lo, const Vec<Dim>& hi, const Vec<Dim>& r) {
  for (int d = 0; d < Dim; ++d)
    if (std::max({lo[d] - p[d], 0.0, p[d] - hi[d]}) >= r[d]) return false;
  return true;
}

// Slack on the reach test: the pair test r < reach is evaluated from the positions differently
// than the box distance, so a pair exactly at the edge must not be lost to rounding.
constexpr double kSlack = 1.0 + 1e-9;

} // namespace

template <int Dim> Vec<Dim> HaloExchange<Dim>::shiftOf(std::uint8_t code) const {
  Vec<Dim> s = Vec<Dim>::Zero();
  for (const auto& p : periodic_) {
    const int t = code % 3;
    code = static_cast<std::uint8_t>(code / 3);
    const double L = p.max - p.min;
    if (t == 1) s[p.axis] += L;
    if (t == 2) s[p.axis] -= L;
  }
  return s;
}

template <int Dim>
void HaloExchange<Dim>::plan(std::span<const Vec<Dim>> x, std::span<const Vec<Dim>> reach,
                             std::span<const double> radius) {
  rows_.assign(static_cast<std::size_t>(size_), {});
  codes_.assign(static_cast<std::size_t>(size_), {});
  Vec<Dim> reachMax = Vec<Dim>::Zero();
  for (const auto& u : rankBox_) reachMax = reachMax.cwiseMax(u.reach);
  // j reaches box b, or a particle in b reaches j: within the larger of both radii, and for
  // ellipsoids also within the larger of both half-widths along every axis (an ellipsoid lies
  // inside both its enclosing sphere and its bounding box).
  const auto near = [&](std::size_t j, const Vec<Dim>& xs, const Box& b) {
    const double rr = std::max(radius[j], b.radius) * kSlack;
    if (distance2<Dim>(xs, b.lo, b.hi) >= rr * rr) return false;
    return round_ || withinPerAxis<Dim>(xs, b.lo, b.hi, reach[j].cwiseMax(b.reach) * kSlack);
  };
  std::vector<std::uint8_t> shifts;
  for (std::size_t j = 0; j < x.size(); ++j) {
    const Vec<Dim>& xj = x[j];
    if (!xj.allFinite()) continue;
    // Periodic images worth testing: along each periodic axis, +L near min and -L near max.
    shifts.assign(1, 0);
    std::uint8_t weight = 1;
    for (const auto& p : periodic_) {
      const double far = std::max(reachMax[p.axis], reach[j][p.axis]) * kSlack;
      const std::size_t m = shifts.size();
      if (xj[p.axis] - p.min < far)
        for (std::size_t k = 0; k < m; ++k)
          shifts.push_back(static_cast<std::uint8_t>(shifts[k] + weight));
      if (p.max - xj[p.axis] <= far)
        for (std::size_t k = 0; k < m; ++k)
          shifts.push_back(static_cast<std::uint8_t>(shifts[k] + 2 * weight));
      weight = static_cast<std::uint8_t>(weight * 3);
    }
    for (const std::uint8_t code : shifts) {
      const Vec<Dim> xs = code ? Vec<Dim>(xj + shiftOf(code)) : xj;
      for (int r = 0; r < size_; ++r) {
        if (r == rank_ && code == 0) continue;
        const Box& u = rankBox_[static_cast<std::size_t>(r)];
        if (!(u.lo[0] <= u.hi[0]) || !near(j, xs, u)) continue;
        for (int b = 0; b < kBoxes; ++b) {
          const Box& box = boxes_[static_cast<std::size_t>(r * kBoxes + b)];
          if (!(box.lo[0] <= box.hi[0])) continue;
          if (near(j, xs, box)) {
            rows_[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(j));
            codes_[static_cast<std::size_t>(r)].push_back(code);
            break;
          }
        }
      }
    }
  }
}

template <int Dim>
void HaloExchange<Dim>::build(ParticleStore& s, Field<Vec<Dim>> xf, std::span<const double> reach,
                              std::span<const std::size_t> fields) {
  const std::size_t n = s.localCount();
  reachScratch_.resize(n);
  for (std::size_t i = 0; i < n; ++i) reachScratch_[i] = Vec<Dim>::Constant(reach[i]);
  round_ = true;
  buildWith(s, xf, reach.first(n), fields);
}

template <int Dim>
void HaloExchange<Dim>::build(ParticleStore& s, Field<Vec<Dim>> xf, std::span<const double> radius,
                              std::span<const Vec<Dim>> halfWidth,
                              std::span<const std::size_t> fields) {
  const std::size_t n = s.localCount();
  reachScratch_.assign(halfWidth.begin(), halfWidth.begin() + static_cast<std::ptrdiff_t>(n));
  round_ = false;
  buildWith(s, xf, radius.first(n), fields);
}

template <int Dim>
void HaloExchange<Dim>::buildWith(ParticleStore& s, Field<Vec<Dim>> xf,
                                  std::span<const double> radius,
                                  std::span<const std::size_t> fields) {
  s.dropGhosts();
  const std::size_t n = s.localCount();
  const auto x = std::span<const Vec<Dim>>(s[xf]).first(n);
  describeDomains(x, reachScratch_, radius);
  plan(x, reachScratch_, radius);

  std::vector<std::size_t> countTo(static_cast<std::size_t>(size_));
  for (int r = 0; r < size_; ++r)
    countTo[static_cast<std::size_t>(r)] = rows_[static_cast<std::size_t>(r)].size();
  // The shift codes double as the counts' exchange.
  std::vector<std::byte> codes;
  for (const auto& c : codes_)
    for (std::uint8_t v : c) codes.push_back(static_cast<std::byte>(v));
  const ExchangeResult in = exchangeBytes(comm_, codes, countTo);
  received_ = in.data.size();
  shifts_.resize(received_);
  for (std::size_t k = 0; k < received_; ++k) shifts_[k] = static_cast<std::uint8_t>(in.data[k]);
  position_ = xf.index;
  first_ = s.appendGhosts(received_);
  refresh(s, fields);
}

template <int Dim>
void HaloExchange<Dim>::refresh(ParticleStore& s, std::span<const std::size_t> fields) {
  receiveRows(s, fields, sendRows(comm_, s, fields, rows_), first_);
  if (std::find(fields.begin(), fields.end(), position_) == fields.end()) return;
  auto xs = s[Field<Vec<Dim>>{position_}];
  for (std::size_t k = 0; k < received_; ++k)
    if (shifts_[k]) xs[first_ + k] += shiftOf(shifts_[k]);
}

template class HaloExchange<1>;
template class HaloExchange<2>;
template class HaloExchange<3>;

} // namespace spall::parallel
