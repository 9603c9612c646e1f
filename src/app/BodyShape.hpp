#pragma once
// A body's shape as the generators test it, and the sites they make (BodyGenerator.cpp,
// GradedSites.cpp).
#include "spall/core/Types.hpp"
#include "spall/io/Deck.hpp"

#include <cmath>
#include <numbers>
#include <vector>

namespace spall::app::sites {

template <int Dim> Vec<Dim> toVec(const std::vector<double>& a) {
  Vec<Dim> v = Vec<Dim>::Zero();
  for (int d = 0; d < Dim && d < static_cast<int>(a.size()); ++d) v[d] = a[d];
  return v;
}

template <int Dim> struct Shape {
  const ShapeConfig& c;
  Vec<Dim> center() const {
    switch (c.type) {
    case ShapeType::Box:
      return 0.5 * (toVec<Dim>(c.min) + toVec<Dim>(c.max));
    case ShapeType::Cylinder:
      return toVec<Dim>(c.base) + 0.5 * c.length * toVec<Dim>(c.axis).normalized();
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
      return std::hypot(c.radius, 0.5 * c.length);
    case ShapeType::Ring:
      return c.outer_radius;
    case ShapeType::Sphere:
      break;
    }
    return c.radius;
  }
  // Length, area or volume (Dim).
  double measure() const {
    const double pi = std::numbers::pi;
    switch (c.type) {
    case ShapeType::Box:
      return (toVec<Dim>(c.max) - toVec<Dim>(c.min)).prod();
    case ShapeType::Cylinder:
      return pi * c.radius * c.radius * c.length;
    case ShapeType::Ring:
      return pi * (c.outer_radius * c.outer_radius - c.inner_radius * c.inner_radius);
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
    case ShapeType::Cylinder:
      break;
    }
    const Vec<Dim> axis = toVec<Dim>(c.axis).normalized();
    const Vec<Dim> rel = x - toVec<Dim>(c.base);
    const double t = rel.dot(axis);
    return t >= 0.0 && t < c.length && (rel - t * axis).norm() < c.radius;
  }
};

// A particle's place and the volume it stands for (an area in 2D and rz, a length in 1D).
template <int Dim> struct Site {
  Vec<Dim> x;
  double volume;
};

} // namespace spall::app::sites
