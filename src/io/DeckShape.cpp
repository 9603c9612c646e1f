// A body's shape, {type = "box" | "sphere" | "cylinder" | "ring", ...} (called from Deck.cpp).
#include "DeckDetail.hpp"

namespace spall::io::deck_detail {

namespace {

// In geometry 'rz' a round shape is a body of revolution: centred on the axis (a sphere, a
// shell) or clear of it (a torus); one that straddles the axis would be two bodies in one.
void checkAxisymmetric(const TableReader& r, bool rz, double centerR, double radius) {
  if (!rz || centerR == 0.0 || centerR - radius >= 0.0) return;
  r.fail("center", r.quoted("center") + " has r = " + formatNumber(centerR) +
                       ": in geometry 'rz' a round shape is centred on the axis (r = 0) or lies "
                       "clear of it (r - radius >= 0)");
}

} // namespace

void readShape(const TableReader& r, ShapeConfig& s, std::size_t dimension, bool rz) {
  const auto point = [&](std::string_view key) {
    return r.required(r.vector(key, dimension), key);
  };
  s.where = r.where();
  const std::string type = r.choice("type", typeNames("body.shape"), std::nullopt);
  s.type = kShapeNames.at(type);
  const std::string dims = "; run.dimension is " + std::to_string(dimension) + ")";
  if (s.type == ShapeType::Cylinder && dimension != 3)
    r.fail("type", "shape 'cylinder' is 3D only (use 'sphere' or 'box' in 1D and 2D" + dims);
  if (s.type == ShapeType::Ring && dimension != 2)
    r.fail("type", "shape 'ring' is 2D only (use 'sphere' or 'box' in 1D and 3D" + dims);
  allowTypedKeys(r, "body.shape", type, "shape");

  switch (s.type) {
  case ShapeType::Box:
    s.min = point("min");
    s.max = point("max");
    for (std::size_t a = 0; a < dimension; ++a)
      if (!(s.min[a] < s.max[a]))
        r.fail("max", r.quoted("max") + " must exceed min on every axis (axis " +
                          std::to_string(a) + ": min " + formatNumber(s.min[a]) + ", max " +
                          formatNumber(s.max[a]) + ")");
    if (rz && s.min[0] < 0.0)
      r.fail("min", r.quoted("min") + " has r = " + formatNumber(s.min[0]) +
                        " < 0: in geometry 'rz' x is the radius (the axis at r = 0)");
    break;
  case ShapeType::Sphere:
    s.center = point("center");
    s.radius = r.required(r.number("radius"), "radius");
    r.check(s.radius > 0.0, "radius", "> 0", s.radius);
    checkAxisymmetric(r, rz, s.center[0], s.radius);
    break;
  case ShapeType::Cylinder:
    s.base = point("base");
    s.axis = point("axis");
    if (norm(s.axis) == 0.0) r.fail("axis", r.quoted("axis") + " must not be the zero vector");
    s.radius = r.required(r.number("radius"), "radius");
    r.check(s.radius > 0.0, "radius", "> 0", s.radius);
    s.length = r.required(r.number("length"), "length");
    r.check(s.length > 0.0, "length", "> 0", s.length);
    break;
  case ShapeType::Ring:
    s.center = point("center");
    s.inner_radius = r.required(r.number("inner_radius"), "inner_radius");
    r.check(s.inner_radius >= 0.0, "inner_radius", ">= 0", s.inner_radius);
    s.outer_radius = r.required(r.number("outer_radius"), "outer_radius");
    r.check(s.inner_radius < s.outer_radius, "inner_radius",
            "< outer_radius (" + formatNumber(s.outer_radius) + ")", s.inner_radius);
    checkAxisymmetric(r, rz, s.center[0], s.outer_radius);
    break;
  }
}

} // namespace spall::io::deck_detail
