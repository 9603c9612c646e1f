#pragma once
// A body's shape as the generators test it, and the sites they make (BodyGenerator.cpp,
// GradedSites.cpp).
#include "spall/core/Types.hpp"
#include "spall/io/Deck.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace spall::app::sites {

template <int Dim> Vec<Dim> toVec(const std::vector<double>& a) {
  Vec<Dim> v = Vec<Dim>::Zero();
  for (int d = 0; d < Dim && d < static_cast<int>(a.size()); ++d) v[d] = a[d];
  return v;
}

// A tangent ogive's local radius at the distance t from its base (Dim 2 and 3 alike): an arc of
// radius rho_o = (R^2 + L^2)/(2R) tangent to the shank at the base and meeting the axis at the
// tip, y(t) = R - rho_o + sqrt(rho_o^2 - t^2) (e.g. Chin, "Missile Configuration Design", 1961).
inline double ogiveRadius(double R, double L, double t) {
  const double rho = (R * R + L * L) / (2.0 * R);
  return R - rho + std::sqrt(std::max(0.0, rho * rho - t * t));
}

template <int Dim> struct Shape {
  const ShapeConfig& c;

  // The part a composite's lattice follows (a union's first, a difference's base): a rod with
  // a nose gets the rod's lattice.
  const ShapeConfig& primary() const {
    const ShapeConfig* p = &c;
    while ((p->type == ShapeType::Union || p->type == ShapeType::Difference) && !p->parts.empty())
      p = &p->parts.front();
    return *p;
  }
  Vec<Dim> center() const {
    switch (c.type) {
    case ShapeType::Box:
      return 0.5 * (toVec<Dim>(c.min) + toVec<Dim>(c.max));
    case ShapeType::Cylinder:
    case ShapeType::Cone:
    case ShapeType::Ogive:
      return toVec<Dim>(c.base) + 0.5 * c.length * toVec<Dim>(c.axis).normalized();
    case ShapeType::Polygon:
    case ShapeType::Particles: {
      const auto [lo, hi] = bounds();
      return 0.5 * (lo + hi);
    }
    case ShapeType::Union:
    case ShapeType::Difference:
      return Shape{primary()}.center();
    case ShapeType::Sphere:
    case ShapeType::Ring:
      break;
    }
    return toVec<Dim>(c.center);
  }
  // Radius of a ball about center() that holds the shape.
  double extent() const {
    switch (c.type) {
    case ShapeType::Box:
      return 0.5 * (toVec<Dim>(c.max) - toVec<Dim>(c.min)).norm();
    case ShapeType::Cylinder:
    case ShapeType::Cone:
    case ShapeType::Ogive:
      return std::hypot(c.radius, 0.5 * c.length);
    case ShapeType::Ring:
      return c.outer_radius;
    case ShapeType::Polygon: {
      double e = 0.0;
      const Vec<Dim> m = center();
      for (const auto& p : c.points) e = std::max(e, (toVec<Dim>(p) - m).norm());
      return e;
    }
    case ShapeType::Particles: {
      const auto [lo, hi] = bounds();
      return 0.5 * (hi - lo).norm();
    }
    case ShapeType::Union: {
      const Vec<Dim> m = center();
      double e = 0.0;
      for (const auto& p : c.parts) {
        const Shape part{p};
        e = std::max(e, (part.center() - m).norm() + part.extent());
      }
      return e;
    }
    case ShapeType::Difference:
      return Shape{c.parts.front()}.extent();
    case ShapeType::Sphere:
      break;
    }
    return c.radius;
  }
  // An axis-aligned box that holds the shape: {lo, hi}.
  std::pair<Vec<Dim>, Vec<Dim>> bounds() const {
    switch (c.type) {
    case ShapeType::Box:
      return {toVec<Dim>(c.min), toVec<Dim>(c.max)};
    case ShapeType::Polygon: {
      Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (const auto& p : c.points)
        lo = lo.cwiseMin(toVec<Dim>(p)), hi = hi.cwiseMax(toVec<Dim>(p));
      return {lo, hi};
    }
    case ShapeType::Particles: {
      const Vec<Dim> half = Vec<Dim>::Constant(0.5 * c.cloud->coarsest);
      return {toVec<Dim>(c.cloud->lo) - half, toVec<Dim>(c.cloud->hi) + half};
    }
    case ShapeType::Union: {
      Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (const auto& p : c.parts) {
        const auto [l, h] = Shape{p}.bounds();
        lo = lo.cwiseMin(l), hi = hi.cwiseMax(h);
      }
      return {lo, hi};
    }
    case ShapeType::Difference:
      return Shape{c.parts.front()}.bounds();
    default:
      break;
    }
    const Vec<Dim> m = center(), e = Vec<Dim>::Constant(extent());
    return {m - e, m + e};
  }
  // Length, area or volume (Dim); a union's and a difference's an upper bound (the sum of the
  // parts', the base's): what the generator sizes its estimate by.
  double measure() const {
    const double pi = std::numbers::pi;
    switch (c.type) {
    case ShapeType::Box:
      return (toVec<Dim>(c.max) - toVec<Dim>(c.min)).prod();
    case ShapeType::Cylinder:
      return pi * c.radius * c.radius * c.length;
    case ShapeType::Ring:
      return pi * (c.outer_radius * c.outer_radius - c.inner_radius * c.inner_radius);
    case ShapeType::Cone: {
      const double R = c.radius, r = c.tip_radius;
      return Dim == 3 ? pi * c.length * (R * R + R * r + r * r) / 3.0 : c.length * (R + r);
    }
    case ShapeType::Ogive: {
      // Simpson's rule on the profile (an estimate's measure: 1e-6 is plenty).
      constexpr int n = 64;
      double sum = 0.0;
      for (int k = 0; k <= n; ++k) {
        const double y = ogiveRadius(c.radius, c.length, c.length * k / n);
        const double w = k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0);
        sum += w * (Dim == 3 ? pi * y * y : 2.0 * y);
      }
      return sum * c.length / (3.0 * n);
    }
    case ShapeType::Polygon: {
      double a = 0.0;
      for (std::size_t k = 0; k < c.points.size(); ++k) {
        const auto& p = c.points[k];
        const auto& q = c.points[(k + 1) % c.points.size()];
        a += p[0] * q[1] - q[0] * p[1];
      }
      return 0.5 * std::abs(a);
    }
    case ShapeType::Particles: {
      double v = 0.0;
      for (double x : c.cloud->volume) v += x;
      return v;
    }
    case ShapeType::Union: {
      double v = 0.0;
      for (const auto& p : c.parts) v += Shape{p}.measure();
      return v;
    }
    case ShapeType::Difference:
      return Shape{c.parts.front()}.measure();
    case ShapeType::Sphere:
      break;
    }
    return Dim == 1   ? 2.0 * c.radius
           : Dim == 2 ? pi * c.radius * c.radius
                      : 4.0 / 3.0 * pi * std::pow(c.radius, 3);
  }
  bool contains(const Vec<Dim>& x) const {
    switch (c.type) {
    case ShapeType::Box:
      for (int d = 0; d < Dim; ++d)
        if (x[d] < c.min[d] || x[d] >= c.max[d]) return false;
      return true;
    case ShapeType::Sphere:
      return (x - toVec<Dim>(c.center)).norm() < c.radius;
    case ShapeType::Ring: {
      const double r = (x - toVec<Dim>(c.center)).norm();
      return r >= c.inner_radius && r < c.outer_radius;
    }
    case ShapeType::Polygon:
      return insidePolygon(x);
    case ShapeType::Union:
      for (const auto& p : c.parts)
        if (Shape{p}.contains(x)) return true;
      return false;
    case ShapeType::Difference:
      if (!Shape{c.parts.front()}.contains(x)) return false;
      for (std::size_t k = 1; k < c.parts.size(); ++k)
        if (Shape{c.parts[k]}.contains(x)) return false;
      return true;
    case ShapeType::Particles:
      // A cloud's region is its particles' cells: the generator asks its sites (ParticleRegion).
      throw std::logic_error("internal: a 'particles' shape has no contains()");
    case ShapeType::Cylinder:
    case ShapeType::Cone:
    case ShapeType::Ogive:
      break;
    }
    // Bodies of revolution about the axis from the base: t along it, rho across.
    const Vec<Dim> axis = toVec<Dim>(c.axis).normalized();
    const Vec<Dim> rel = x - toVec<Dim>(c.base);
    const double t = rel.dot(axis);
    if (!(t >= 0.0 && t < c.length)) return false;
    const double rho = (rel - t * axis).norm();
    if (c.type == ShapeType::Cylinder) return rho < c.radius;
    if (c.type == ShapeType::Cone)
      return rho < c.radius + (c.tip_radius - c.radius) * (t / c.length);
    return rho < ogiveRadius(c.radius, c.length, t);
  }

private:
  // Crossing number of a ray along +x (even-odd rule; a point on a lower edge is inside, on an
  // upper one outside, as the box's [min, max) is).
  bool insidePolygon(const Vec<Dim>& x) const {
    if constexpr (Dim != 2) {
      return false;
    } else {
      bool in = false;
      const std::size_t n = c.points.size();
      for (std::size_t k = 0, l = n - 1; k < n; l = k++) {
        const double xk = c.points[k][0], yk = c.points[k][1];
        const double xl = c.points[l][0], yl = c.points[l][1];
        if ((yk > x[1]) != (yl > x[1]) && x[0] < xl + (x[1] - yl) * (xk - xl) / (yk - yl)) in = !in;
      }
      return in;
    }
  }
};

// A particle's place and the volume it stands for (an area in 2D and rz, a length in 1D).
template <int Dim> struct Site {
  Vec<Dim> x;
  double volume;
};

} // namespace spall::app::sites
