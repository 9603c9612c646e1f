#include "spall/parallel/HaloExchange.hpp"

#include "spall/parallel/Exchange.hpp"
#include "spall/parallel/RowExchange.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall::parallel {

template <int Dim>
HaloExchange<Dim>::HaloExchange(MPI_Comm comm, std::vector<PeriodicAxis> periodic)
    : comm_(comm), targets_(std::move(periodic)) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

// Every rank's kHaloBoxes boxes (HaloBoxes.hpp), gathered.
template <int Dim>
void HaloExchange<Dim>::describeDomains(std::span<const Vec<Dim>> x,
                                        std::span<const Vec<Dim>> reach,
                                        std::span<const double> radius, bool round) {
  constexpr int per = 3 * Dim + 1;
  const auto boxes = describeBoxes<Dim>(x, reach, radius);
  std::vector<double> mine(static_cast<std::size_t>(kHaloBoxes * per));
  for (int b = 0; b < kHaloBoxes; ++b) {
    const HaloBox<Dim>& box = boxes[static_cast<std::size_t>(b)];
    double* out = &mine[static_cast<std::size_t>(b * per)];
    for (int d = 0; d < Dim; ++d)
      out[d] = box.lo[d], out[Dim + d] = box.hi[d], out[2 * Dim + d] = box.reach[d];
    out[3 * Dim] = box.radius;
  }
  std::vector<double> all(mine.size() * static_cast<std::size_t>(size_));
  MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(),
                static_cast<int>(mine.size()), MPI_DOUBLE, comm_);
  std::vector<HaloBox<Dim>> every(all.size() / per);
  for (std::size_t k = 0; k < every.size(); ++k) {
    HaloBox<Dim>& b = every[k];
    for (int d = 0; d < Dim; ++d)
      b.lo[d] = all[k * per + d], b.hi[d] = all[k * per + Dim + d],
      b.reach[d] = all[k * per + 2 * Dim + d];
    b.radius = all[k * per + 3 * Dim];
  }
  targets_.setBoxes(std::move(every), round);
}

template <int Dim>
void HaloExchange<Dim>::plan(std::span<const Vec<Dim>> x, std::span<const Vec<Dim>> reach,
                             std::span<const double> radius) {
  rows_.assign(static_cast<std::size_t>(size_), {});
  codes_.assign(static_cast<std::size_t>(size_), {});
  const auto everyRank = [this](const Vec<Dim>&, auto&& visit) {
    for (int r = 0; r < size_; ++r) visit(r);
  };
  for (std::size_t j = 0; j < x.size(); ++j)
    targets_.targets(x[j], reach[j], radius[j], rank_, everyRank, [&](int r, std::uint8_t code) {
      rows_[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(j));
      codes_[static_cast<std::size_t>(r)].push_back(code);
    });
}

template <int Dim>
void HaloExchange<Dim>::build(ParticleStore& s, Field<Vec<Dim>> xf, std::span<const double> reach,
                              std::span<const std::size_t> fields) {
  const std::size_t n = s.localCount();
  reachScratch_.resize(n);
  for (std::size_t i = 0; i < n; ++i) reachScratch_[i] = Vec<Dim>::Constant(reach[i]);
  buildWith(s, xf, reach.first(n), fields, true);
}

template <int Dim>
void HaloExchange<Dim>::build(ParticleStore& s, Field<Vec<Dim>> xf, std::span<const double> radius,
                              std::span<const Vec<Dim>> halfWidth,
                              std::span<const std::size_t> fields) {
  const std::size_t n = s.localCount();
  reachScratch_.assign(halfWidth.begin(), halfWidth.begin() + static_cast<std::ptrdiff_t>(n));
  buildWith(s, xf, radius.first(n), fields, false);
}

template <int Dim>
void HaloExchange<Dim>::buildWith(ParticleStore& s, Field<Vec<Dim>> xf,
                                  std::span<const double> radius,
                                  std::span<const std::size_t> fields, bool round) {
  s.dropGhosts();
  const std::size_t n = s.localCount();
  const auto x = std::span<const Vec<Dim>>(s[xf]).first(n);
  describeDomains(x, reachScratch_, radius, round);
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
    if (shifts_[k]) xs[first_ + k] += targets_.shiftOf(shifts_[k]);
}

template class HaloExchange<1>;
template class HaloExchange<2>;
template class HaloExchange<3>;

} // namespace spall::parallel
