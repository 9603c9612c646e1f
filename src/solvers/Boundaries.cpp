#include "spall/solvers/Boundaries.hpp"

#include "spall/core/Threads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall::solvers {

template <int Dim>
Boundaries<Dim>::Boundaries(const std::vector<BoundaryConfig>& config, const ParticleStore& s,
                            const ParticleFields<Dim>& f)
    : x_(f.x), v_(f.v) {
  for (const auto& b : config) {
    switch (b.type) {
    case BoundaryType::RigidWall: {
      Wall w;
      for (int d = 0; d < Dim; ++d) {
        w.point[d] = b.point[d];
        w.normal[d] = b.normal[d];
      }
      w.normal.normalize();
      w.fold = b.fold;
      walls_.push_back(w);
      break;
    }
    case BoundaryType::Periodic:
      periodic_.push_back({b.axis, b.min, b.max});
      break;
    case BoundaryType::Pressure: // loads a body's surface: methods/modules/ConfiningPressure.hpp
      break;
    }
  }
  for (std::size_t c : s.columnsWith(kReflectVector)) vectors_.push_back({c});
  for (std::size_t c : s.columnsWith(kReflectTensor)) {
    if (s.columns()[c]->info().scalarsPerParticle() == 9)
      tensors3_.push_back({c});
    else
      tensors_.push_back({c});
  }
}

template <int Dim> std::size_t Boundaries<Dim>::wrapPeriodic(ParticleStore& s) const {
  const auto x = s[x_];
  const auto v = s[v_];
  std::size_t moved = 0;
  for (const auto& w : walls_) {
    if (!w.fold) continue;
    for (std::size_t i = 0; i < s.localCount(); ++i) {
      const double d = (x[i] - w.point).dot(w.normal);
      if (d >= 0.0) continue;
      x[i] -= 2.0 * d * w.normal;
      v[i] -= 2.0 * v[i].dot(w.normal) * w.normal;
      ++moved;
    }
  }
  for (const auto& pb : periodic_) {
    const double L = pb.max - pb.min;
    for (std::size_t i = 0; i < s.localCount(); ++i) {
      double& xi = x[i][pb.axis];
      if (xi < pb.min || xi >= pb.max) {
        xi -= L * std::floor((xi - pb.min) / L);
        ++moved;
      }
    }
  }
  return moved;
}

template <int Dim>
bool Boundaries<Dim>::crossedWall(std::span<const Vec<Dim>> from,
                                  std::span<const Vec<Dim>> to) const {
  for (const auto& w : walls_)
    for (std::size_t i = 0; i < from.size(); ++i)
      if (((from[i] - w.point).dot(w.normal) < 0.0) != ((to[i] - w.point).dot(w.normal) < 0.0))
        return true;
  return false;
}

template <int Dim>
void Boundaries<Dim>::reflectVector(ParticleStore& s, Field<Vec<Dim>> field, std::size_t k) const {
  auto v = s[field];
  const Vec<Dim>& n = walls_[wallOf_[k]].normal;
  v[first_ + k] -= 2.0 * v[first_ + k].dot(n) * n;
}

template <int Dim>
template <int N>
void Boundaries<Dim>::reflectTensor(ParticleStore& s, Field<Tensor<N>> field, std::size_t k) const {
  auto T = s[field];
  T[first_ + k] = mirrored(T[first_ + k], walls_[wallOf_[k]]);
}

template <int Dim> void Boundaries<Dim>::buildGhosts(ParticleStore& s, double reach) {
  source_.clear();
  wallOf_.clear();
  first_ = s.size();
  firstWallImage_ = std::numeric_limits<std::size_t>::max();
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    const Wall& w = walls_[k];
    if (!w.fold && firstWallImage_ == std::numeric_limits<std::size_t>::max())
      firstWallImage_ = s.size();
    const std::size_t count = s.size(); // owned, remote ghosts and images of earlier walls
    for (std::size_t i = 0; i < count; ++i) {
      const double d = (s[x_][i] - w.point).dot(w.normal);
      if (d < 0.0 || d >= reach) continue;
      const std::size_t g = s.appendGhostCopy(i);
      s[x_][g] -= 2.0 * d * w.normal;
      source_.push_back(static_cast<std::uint32_t>(i));
      wallOf_.push_back(static_cast<std::uint32_t>(k));
      const std::size_t image = source_.size() - 1;
      for (const auto f : vectors_) reflectVector(s, f, image);
      for (const auto f : tensors_) reflectTensor(s, f, image);
      for (const auto f : tensors3_) reflectTensor(s, f, image);
    }
  }
}

template <int Dim>
void Boundaries<Dim>::holdAcceleration(std::span<const Vec<Dim>> x, std::span<const double> h,
                                       std::span<Vec<Dim>> a) const {
  for (const auto& w : walls_) {
    if (w.fold) continue;
#pragma omp parallel for schedule(static) if (threaded(a.size()))
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!held((x[i] - w.point).dot(w.normal), h[i])) continue;
      const double an = a[i].dot(w.normal);
      if (an < 0.0) a[i] -= an * w.normal;
    }
  }
}

template <int Dim>
void Boundaries<Dim>::holdVelocity(std::span<Vec<Dim>> x, std::span<const double> h,
                                   std::span<Vec<Dim>> v, std::span<double> e) const {
  for (const auto& w : walls_) {
    if (w.fold) continue;
#pragma omp parallel for schedule(static) if (threaded(v.size()))
    for (std::size_t i = 0; i < v.size(); ++i) {
      const double d = (x[i] - w.point).dot(w.normal);
      if (!held(d, h[i])) continue;
      if (d < 0.0) x[i] -= d * w.normal; // stepped across: back onto the plane
      const double vn = v[i].dot(w.normal);
      if (vn >= 0.0) continue;
      v[i] -= vn * w.normal;
      e[i] += 0.5 * vn * vn;
    }
  }
}

template <int Dim> std::vector<parallel::PeriodicAxis> Boundaries<Dim>::periodicAxes() const {
  std::vector<parallel::PeriodicAxis> out;
  for (const auto& p : periodic_) out.push_back({p.axis, p.min, p.max});
  return out;
}

template <int Dim>
void Boundaries<Dim>::refreshGhosts(ParticleStore& s, std::span<const std::size_t> columns) const {
  // In creation order, so an image of an image sees its source already refreshed.
  const auto among = [](const auto& list, std::size_t c) {
    return std::any_of(list.begin(), list.end(), [c](const auto f) { return f.index == c; });
  };
  for (const std::size_t c : columns) {
    const bool vector = among(vectors_, c), tensor = among(tensors_, c),
               tensor3 = among(tensors3_, c);
    if (c == x_.index) {
      // As buildGhosts placed it: across the plane from the source.
      const auto x = s[x_];
      for (std::size_t k = 0; k < source_.size(); ++k) {
        const Wall& w = walls_[wallOf_[k]];
        const double d = (x[source_[k]] - w.point).dot(w.normal);
        x[first_ + k] = x[source_[k]];
        x[first_ + k] -= 2.0 * d * w.normal;
      }
      continue;
    }
    for (std::size_t k = 0; k < source_.size(); ++k) {
      s.copyRow(c, source_[k], first_ + k);
      if (vector) reflectVector(s, Field<Vec<Dim>>{c}, k);
      if (tensor) reflectTensor(s, Field<Tensor<Dim>>{c}, k);
      if (tensor3) reflectTensor(s, Field<Tensor<3>>{c}, k);
    }
  }
}

template class Boundaries<1>;
template class Boundaries<2>;
template class Boundaries<3>;

} // namespace spall::solvers
