// A shape's thinnest width and the radius a penetrator of it presents: the resolution
// warnings (particles across a body or a rod's radius) and MPM's thin-body warning read them.
#include "spall/io/Deck.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace spall {

namespace {
// The least width of a polygon's convex hull: across its narrowest direction, which is normal to
// one of the hull's edges (and so to one of the polygon's: every hull edge is one, or bridges a
// dent the polygon is wider than).
double polygonWidth(const std::vector<std::vector<double>>& p) {
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.size(); ++k) {
    const auto& a = p[k];
    const auto& b = p[(k + 1) % p.size()];
    const double ex = b[0] - a[0], ey = b[1] - a[1], len = std::hypot(ex, ey);
    if (len == 0.0) continue;
    double lo = 0.0, hi = 0.0;
    for (const auto& q : p) {
      const double d = ((q[0] - a[0]) * ey - (q[1] - a[1]) * ex) / len;
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    least = std::min(least, hi - lo);
  }
  return least;
}
} // namespace

double thinnestWidth(const ShapeConfig& s) {
  double width = std::numeric_limits<double>::infinity();
  switch (s.type) {
  case ShapeType::Box:
    for (std::size_t a = 0; a < s.min.size() && a < s.max.size(); ++a)
      width = std::min(width, s.max[a] - s.min[a]);
    break;
  case ShapeType::Sphere:
    width = 2.0 * s.radius;
    break;
  case ShapeType::Cylinder:
  case ShapeType::Cone:
  case ShapeType::Ogive:
    width = std::min(2.0 * s.radius, s.length);
    break;
  case ShapeType::Ring:
    width = s.outer_radius - s.inner_radius;
    break;
  case ShapeType::Polygon:
    width = polygonWidth(s.points);
    break;
  case ShapeType::Union:
  case ShapeType::Difference:
    // What a composite is built on (a rod under its nose, the plate a hole is cut from): the
    // parts added to it are no thinner than what they join, and a cut's walls are not known.
    width = s.parts.empty() ? width : thinnestWidth(s.parts.front());
    break;
  case ShapeType::Particles:
    if (s.cloud) {
      for (std::size_t a = 0; a < s.cloud->lo.size(); ++a)
        width = std::min(width, s.cloud->hi[a] - s.cloud->lo[a] + s.cloud->coarsest);
    }
    break;
  }
  return width;
}

double penetratorRadius(const ShapeConfig& s, bool rz) {
  if (rz && s.type == ShapeType::Box && !s.min.empty() && s.min[0] == 0.0) return s.max[0];
  if (s.type == ShapeType::Cylinder || s.type == ShapeType::Sphere || s.type == ShapeType::Cone ||
      s.type == ShapeType::Ogive)
    return s.radius;
  if ((s.type == ShapeType::Union || s.type == ShapeType::Difference) && !s.parts.empty())
    return penetratorRadius(s.parts.front(), rz);
  if (rz && s.type == ShapeType::Polygon) {
    double r = 0.0; // a body of revolution: its widest ring
    for (const auto& p : s.points) r = std::max(r, p[0]);
    return r;
  }
  return 0.5 * thinnestWidth(s);
}

} // namespace spall
