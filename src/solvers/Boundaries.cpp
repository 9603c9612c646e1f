#include "spall/solvers/Boundaries.hpp"

#include <cmath>

namespace spall::solvers {

template <int Dim>
Boundaries<Dim>::Boundaries(const std::vector<BoundaryConfig>& config, const SphFields<Dim>& f)
    : f_(f) {
  for (const auto& b : config) {
    if (b.type == "rigid_wall") {
      Wall w;
      for (int d = 0; d < Dim; ++d) {
        w.point[d] = b.point[d];
        w.normal[d] = b.normal[d];
      }
      w.normal.normalize();
      order_.push_back({true, walls_.size()});
      walls_.push_back(w);
    } else {
      order_.push_back({false, periodic_.size()});
      periodic_.push_back({b.axis, b.min, b.max});
    }
  }
}

template <int Dim> void Boundaries<Dim>::wrapPeriodic(ParticleStore& s) const {
  const auto x = s[f_.x];
  for (const auto& pb : periodic_) {
    const double L = pb.max - pb.min;
    for (std::size_t i = 0; i < s.localCount(); ++i) {
      double& xi = x[i][pb.axis];
      if (xi < pb.min || xi >= pb.max) xi -= L * std::floor((xi - pb.min) / L);
    }
  }
}

template <int Dim> void Boundaries<Dim>::buildGhosts(ParticleStore& s, double reach) {
  s.dropGhosts();
  source_.clear();
  for (const Kind& k : order_) {
    const std::size_t count = s.size(); // owned + ghosts of earlier boundaries
    if (k.wall) {
      const Wall& w = walls_[k.index];
      for (std::size_t i = 0; i < count; ++i) {
        const double d = (s[f_.x][i] - w.point).dot(w.normal);
        if (d < 0.0 || d >= reach) continue;
        const std::size_t g = s.appendGhostCopy(i);
        auto x = s[f_.x];
        auto v = s[f_.v];
        x[g] -= 2.0 * d * w.normal;
        v[g] -= 2.0 * v[g].dot(w.normal) * w.normal;
        source_.push_back(static_cast<std::uint32_t>(i));
      }
    } else {
      const Periodic& pb = periodic_[k.index];
      const double L = pb.max - pb.min;
      for (std::size_t i = 0; i < count; ++i) {
        const double xi = s[f_.x][i][pb.axis];
        for (double shift : {L, -L}) {
          const bool near = shift > 0.0 ? xi - pb.min < reach : pb.max - xi <= reach;
          if (!near) continue;
          const std::size_t g = s.appendGhostCopy(i);
          s[f_.x][g][pb.axis] += shift;
          source_.push_back(static_cast<std::uint32_t>(i));
        }
      }
    }
  }
}

template <int Dim> void Boundaries<Dim>::refreshGhosts(ParticleStore& s) const {
  const auto rho = s[f_.rho];
  const auto p = s[f_.p];
  const auto cs = s[f_.cs];
  const std::size_t first = s.localCount();
  // In creation order, so an image of an image sees its source already refreshed.
  for (std::size_t k = 0; k < source_.size(); ++k) {
    const std::size_t g = first + k, i = source_[k];
    rho[g] = rho[i];
    p[g] = p[i];
    cs[g] = cs[i];
  }
}

template class Boundaries<1>;
template class Boundaries<2>;
template class Boundaries<3>;

} // namespace spall::solvers
