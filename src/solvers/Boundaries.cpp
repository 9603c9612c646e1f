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
      walls_.push_back(w);
    } else {
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
  source_.clear();
  wallOf_.clear();
  first_ = s.size();
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    const Wall& w = walls_[k];
    const std::size_t count = s.size(); // owned, remote ghosts and images of earlier walls
    for (std::size_t i = 0; i < count; ++i) {
      const double d = (s[f_.x][i] - w.point).dot(w.normal);
      if (d < 0.0 || d >= reach) continue;
      const std::size_t g = s.appendGhostCopy(i);
      auto x = s[f_.x];
      auto v = s[f_.v];
      x[g] -= 2.0 * d * w.normal;
      v[g] -= 2.0 * v[g].dot(w.normal) * w.normal;
      if (f_.hasStrength()) {
        auto S = s[f_.S];
        S[g] = mirrored(S[g], w);
      }
      if (f_.anisotropic()) { // the mirror image of the smoothing ellipsoid
        auto H = s[f_.H];
        H[g] = mirrored(H[g], w);
      }
      source_.push_back(static_cast<std::uint32_t>(i));
      wallOf_.push_back(static_cast<std::uint32_t>(k));
    }
  }
}

template <int Dim> std::vector<parallel::PeriodicAxis> Boundaries<Dim>::periodicAxes() const {
  std::vector<parallel::PeriodicAxis> out;
  for (const auto& p : periodic_) out.push_back({p.axis, p.min, p.max});
  return out;
}

template <int Dim>
void Boundaries<Dim>::refreshGhosts(ParticleStore& s,
                                    std::initializer_list<Field<Tensor<3>>> tensors) const {
  const auto rho = s[f_.rho];
  const auto p = s[f_.p];
  const auto cs = s[f_.cs];
  const std::size_t first = first_;
  // In creation order, so an image of an image sees its source already refreshed.
  for (std::size_t k = 0; k < source_.size(); ++k) {
    const std::size_t g = first + k, i = source_[k];
    rho[g] = rho[i];
    p[g] = p[i];
    cs[g] = cs[i];
  }
  for (const auto field : tensors) {
    if (!field.valid()) continue;
    const auto T = s[field];
    for (std::size_t k = 0; k < source_.size(); ++k)
      T[first + k] = mirrored(T[source_[k]], walls_[wallOf_[k]]);
  }
}

template class Boundaries<1>;
template class Boundaries<2>;
template class Boundaries<3>;

} // namespace spall::solvers
