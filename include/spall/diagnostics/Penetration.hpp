#pragma once
// Depth of penetration (penetration.csv; docs/reference.md, [penetration]): the deepest penetrator
// material below the target's original surface along the direction of penetration,
//   depth = max_i (x_i - x_s) . n   over the penetrator's particles,
// the rate of that depth (the difference from the previous row over the time between them), and
// the tip velocity: the mass-weighted mean of v . n over the penetrator particles whose kernel
// support reaches the deepest point, the material at the tip. In a steady penetration the rate
// and the tip velocity are both the penetration velocity U (Austin 2013, Eq. 3.2).
#include "spall/core/ParticleFields.hpp"
#include "spall/diagnostics/OrderFreeSums.hpp"
#include "spall/io/Checkpoint.hpp"
#include "spall/parallel/Mpi.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace spall::diagnostics {

struct PenetrationRow {
  double time = 0.0, depth = 0.0, rate = 0.0, tipVelocity = 0.0;
};

template <int Dim> class PenetrationGauge {
public:
  // penetrator: a flag per body index; support: the kernel's support in units of h.
  PenetrationGauge(std::vector<char> penetrator, const Vec<Dim>& surface, const Vec<Dim>& direction,
                   double support)
      : penetrator_(std::move(penetrator)), surface_(surface), n_(direction), support_(support) {}

  // The row at `time`, or nothing while the penetrator has no particles (a body not yet
  // inserted). The depth is a maximum and the tip velocity's sums order-free: the same bits on
  // any rank count.
  std::optional<PenetrationRow> measure(double time, const ParticleStore& s,
                                        const ParticleFields<Dim>& f,
                                        const parallel::MpiContext& mpi) {
    const auto x = s[f.x];
    const auto v = s[f.v];
    const auto m = s[f.m];
    const auto h = s[f.h];
    const auto body = s[f.body];
    const std::size_t n = s.localCount();
    double deepest = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i)
      if (isPenetrator(body[i])) deepest = std::max(deepest, (x[i] - surface_).dot(n_));
    deepest = mpi.max(deepest);
    if (deepest == -std::numeric_limits<double>::infinity()) return std::nullopt;
    // sum m v.n and sum m over the tip's particles, order-free (the same bits on any rank count)
    const auto tip = orderFreeSums<2>(
        n,
        [&](std::size_t i, std::span<double> t) {
          const bool atTip =
              isPenetrator(body[i]) && (x[i] - surface_).dot(n_) >= deepest - support_ * h[i];
          t[0] = atTip ? m[i] * v[i].dot(n_) : 0.0;
          t[1] = atTip ? m[i] : 0.0;
        },
        mpi.comm());
    PenetrationRow row{time, deepest, 0.0, tip[0] / tip[1]};
    // The first row has no earlier one to difference with: its rate is the tip's velocity.
    row.rate = hasPrevious_ && time > previousTime_
                   ? (deepest - previousDepth_) / (time - previousTime_)
                   : row.tipVelocity;
    hasPrevious_ = true;
    previousTime_ = time;
    previousDepth_ = deepest;
    return row;
  }

  // The previous row, so that a restarted run's first rate is the one the run would have written.
  void save(io::CheckpointState& st) const {
    st.reals["penetration_previous"] = {hasPrevious_ ? 1.0 : 0.0, previousTime_, previousDepth_};
  }
  void restore(const io::CheckpointState& st) {
    const auto it = st.reals.find("penetration_previous");
    if (it == st.reals.end() || it->second.size() != 3) return; // written before [penetration]
    hasPrevious_ = it->second[0] != 0.0;
    previousTime_ = it->second[1];
    previousDepth_ = it->second[2];
  }

private:
  bool isPenetrator(std::int32_t body) const {
    return body >= 0 && static_cast<std::size_t>(body) < penetrator_.size() &&
           penetrator_[static_cast<std::size_t>(body)];
  }

  std::vector<char> penetrator_;
  Vec<Dim> surface_, n_;
  double support_;
  bool hasPrevious_ = false;
  double previousTime_ = 0.0, previousDepth_ = 0.0;
};

} // namespace spall::diagnostics
