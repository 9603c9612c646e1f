// [[body]], its shapes and velocity fields, and [[jet]]: the reference's rows and the reader's
// reads (Keys.hpp); io/Deck.cpp checks the material they name, io/DeckJet.cpp makes a jet's
// segments.
#include "Keys.hpp"

#include "spall/io/ParticleFile.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

namespace spall::io::keys {

namespace {

template <class K> void keysOf(K& k, BodyConfig& b) {
  k.section("", "A body: a shape filled with particles of one material on a lattice.");
  k.other("name", "string", "required", "", "unique, non-empty, no '.'",
          "What boundaries, probes and diagnostics call it by; --set addresses body.NAME.");
  k.text("material", b.material, required, "a [[material]]'s name",
         "The material its particles are made of.");
  k.table("shape", "required", "", "The region it fills: {type = ..., ...}.");
  k.number("spacing", b.spacing,
           Depends{"required, except with a 'particles' shape (the file's volumes)"}, "m", above(0),
           "The lattice spacing of its particles, divided by run.resolution.");
  k.choice("lattice", b.lattice, kLatticeNames, keep,
           "hexagonal: triangular in 2D, hexagonal close packing in 3D.");
  k.note("spacing", "warns under 3 particles across the body's thinnest extent, or a "
                    "penetrator's radius (a gradient needs a particle either side)");
  k.vector("velocity", b.velocity, Depends{"zero"}, "m/s", "slower than light",
           "Its uniform initial velocity, to which the velocity fields add.");
  k.note("velocity", "warns above 1e5 m/s (mm/s or cm/s typed?), and for a [penetration] "
                     "penetrator below 10 m/s (km/s typed?)");
  k.number("initial_density", b.initial_density,
           Depends{"the material's density (over alpha0 if porous)"}, "kg/m^3", above(0),
           "The starting density of its particles.");
  k.number("initial_specific_energy", b.initial_specific_energy, Depends{"0.0"}, "J/kg", atLeast(0),
           "The starting internal energy.");
  k.note("initial_specific_energy", "not with initial_pressure");
  k.number("initial_pressure", b.initial_pressure, off, "Pa", any(),
           "The starting pressure: sets the energy from the eos (a cap material's density).");
  // Both would set the internal energy; which one wins is not for the reader to guess.
  k.require("initial_pressure", "not with initial_specific_energy",
            !b.initial_pressure || !b.initial_specific_energy,
            "cannot be combined with initial_specific_energy (both set the internal energy; give "
            "one)");
  k.number("jitter", b.jitter, keep, "", withinClosedOpen(0, 0.5),
           "Random offsets of the particles, a fraction of the spacing (seeded by run.seed).");
  k.table("radial_velocity", "none", "",
          "Adds a velocity along x - center: {center = [...], speed = ...}.");
  k.number("insert_time", b.insert_time, keep, "s", atLeast(0),
           "The time it joins the run; until then it is absent (may overlap other bodies).");
  k.matrix("lattice_transform", b.lattice_transform, off, "", "invertible",
           "A matrix applied to the lattice about the shape's centre (sheared or turned sites).");
  k.flag("allow_overlap", b.allow_overlap, keep,
         "It may overlap bodies listed before it (their shapes are not checked).");
  k.table("cantilever_velocity", "none", "dimension 2 or 3",
          "Adds a beam's first bending mode as a y velocity: {root, length, tip_speed}.");
  k.table("linear_velocity", "none", "",
          "Adds v = G (x - center): a homogeneous stretch, shear or "
          "spin.");
  k.flag("fixed", b.fixed, keep,
         "Moves rigidly at its uniform velocity: at rest a clamp, else a piston; bears stress.");
  k.note("fixed", "no velocity field");
  k.table("sine_velocity", "none", "",
          "Adds v = amplitude sin(wavevector . (x - origin)), a standing wave's velocity.");
  k.table("grading", "none", "SPH and ASPH; a cubic lattice",
          "Graded spacing: {within, ratio, max_spacing} from a point, line or plane.");
}

template <class K> void keysOf(K& k, GradingConfig& g) {
  k.section("", "Graded spacing: `spacing` within `within` of the reference, then layers each "
                "`ratio` times thicker than the one before, up to `max_spacing`.");
  k.number("within", g.within, required, "m", atLeast(0),
           "The distance from the reference kept at the body's spacing.");
  k.number("ratio", g.ratio, keep, "", within(1.0, 2.0),
           "The growth of the spacing from one layer to the next.");
  k.note("ratio",
         "a plane wave crossing the layers reflects 0.9% of its amplitude at 1.05, 0.3% at 1.02 "
         "(decks/graded_plane_wave_1d.toml)");
  k.number("max_spacing", g.max_spacing, required, "m", above(0),
           "The largest spacing, divided by run.resolution; at least the body's spacing.");
  k.vector("point", g.point, Depends{"one of point, line, plane"}, "m", "",
           "A point reference: layers are spherical shells (rings in 2D) about it.");
  k.table("line", "none", "2D or 3D",
          "A line reference {point, direction}: layers are cylinders about it (strips in 2D).");
  k.table("plane", "none", "", "A plane reference {point, normal}: layers are slabs along it.");
}

template <class K> void keysOf(K& k, GradingLine& l) {
  k.section("", "A line from which a graded body's spacing grows.");
  k.vector("point", l.point, required, "m", "", "A point on the line.");
  k.vector("direction", l.direction, required, "", "not zero", "Its direction (any length).");
}

template <class K> void keysOf(K& k, GradingPlane& p) {
  k.section("", "A plane from which a graded body's spacing grows (on both sides).");
  k.vector("point", p.point, required, "m", "", "A point on the plane.");
  k.vector("normal", p.normal, required, "", "not zero", "Its normal (any length).");
}

template <class K> void boxKeys(K& k, ShapeConfig& s) {
  k.section("box", "An axis-aligned box, filled exactly by a cubic lattice.");
  k.vector("min", s.min, required, "m", "in rz: r >= 0", "The lowest corner.");
  k.vector("max", s.max, required, "m", "> min on every axis", "The highest corner.");
}

template <class K> void sphereKeys(K& k, ShapeConfig& s) {
  k.section("sphere", "A ball: a disk in 2D, a segment in 1D; in rz centred on the axis or clear "
                      "of it (a torus).");
  k.vector("center", s.center, required, "m", "in rz: r = 0 or r >= radius", "The centre.");
  k.number("radius", s.radius, required, "m", above(0), "The radius.");
}

template <class K> void cylinderKeys(K& k, ShapeConfig& s) {
  k.section("cylinder", "A circular cylinder, 3D only.");
  k.vector("base", s.base, required, "m", "", "The centre of one end face.", "float[3]");
  k.vector("axis", s.axis, required, "", "not zero",
           "The direction from the base to the other end (any length).", "float[3]");
  k.number("radius", s.radius, required, "m", above(0), "The radius.");
  k.number("length", s.length, required, "m", above(0), "The length along the axis.");
}

template <class K> void ringKeys(K& k, ShapeConfig& s) {
  k.section("ring", "An annulus, 2D only.");
  k.vector("center", s.center, required, "m", "in rz: r = 0 or r >= outer_radius", "The centre.",
           "float[2]");
  k.number("inner_radius", s.inner_radius, required, "m", atLeast(0), "The radius of the hole.");
  k.note("inner_radius", "< outer_radius");
  k.number("outer_radius", s.outer_radius, required, "m", above("inner_radius", s.inner_radius),
           "The outer radius.");
}

template <class K> void coneKeys(K& k, ShapeConfig& s) {
  k.section("cone", "A cone or a frustum about an axis (2D: its section, a trapezoid; rz: about "
                    "the z axis), a penetrator's conical nose.");
  k.vector("base", s.base, required, "m", "in rz: on the axis (r = 0)",
           "The centre of the base, the wider end.");
  k.vector("axis", s.axis, required, "", "not zero; in rz along z",
           "The direction from the base to the tip (any length).");
  k.number("radius", s.radius, required, "m", above(0), "The radius of the base.");
  k.number("length", s.length, required, "m", above(0), "The length from the base to the tip.");
  k.number("tip_radius", s.tip_radius, keep, "m", withinClosedOpen(0, "radius", s.radius),
           "The radius at the tip: 0 a point, else a frustum's flat.");
}

template <class K> void ogiveKeys(K& k, ShapeConfig& s) {
  k.section("ogive", "A tangent ogive about an axis (2D: its section; rz: about the z axis): the "
                     "arc of radius (R^2 + L^2)/(2R) that meets the shank tangentially at the base "
                     "and the axis at the tip.");
  k.vector("base", s.base, required, "m", "in rz: on the axis (r = 0)",
           "The centre of the base, where the nose meets the shank.");
  k.vector("axis", s.axis, required, "", "not zero; in rz along z",
           "The direction from the base to the tip (any length).");
  k.number("radius", s.radius, required, "m", above(0), "R, the shank's radius.");
  k.number("length", s.length, required, "m", atLeast("radius", s.radius),
           "L, the nose's length; L = R is a hemisphere, a caliber-radius-head of n has "
           "L = R sqrt(4n - 1).");
}

template <class K> void polygonKeys(K& k, ShapeConfig& s) {
  k.section("polygon", "A simple polygon, 2D and rz (revolved about the axis): any section.");
  k.other("points", "float[2][]", "required", "m",
          "3 or more; edges that do not cross; in rz: r >= 0",
          "Its vertices in order round it (either way), the last joined to the first.");
  (void)s;
}

template <class K> void unionKeys(K& k, ShapeConfig& s) {
  k.section("union", "Every point of any of its shapes: a rod with a nose, an assembly of one "
                     "material. The lattice is the first shape's (a box's exact lattice carried "
                     "over the rest).");
  k.other("shapes", "[table]", "required", "", "2 or more shapes, any type but 'particles'",
          "The shapes joined: [{type = ..., ...}, ...].");
  (void)s;
}

template <class K> void differenceKeys(K& k, ShapeConfig& s) {
  k.section("difference", "A shape with others cut out of it: a hollow charge's liner, a plate "
                          "with a hole. The lattice is `from`'s.");
  k.other("from", "table", "required", "", "any type but 'particles'",
          "The shape cut from: {type = ..., ...}.");
  k.other("minus", "[table]", "required", "", "1 or more shapes, any type but 'particles'",
          "The shapes cut out: [{type = ..., ...}, ...].");
  (void)s;
}

template <class K> void particlesKeys(K& k, ShapeConfig& s) {
  k.section("particles", "Particles read from a file (a mesher's): their positions and the "
                         "volumes they stand for (in 2D and rz the cell's area in the plane, in "
                         "1D its length). run.resolution and lattice do not apply; the body takes "
                         "no spacing (each particle's is its volume's root).");
  k.text("file", s.file, required,
         "CSV (header x[,y[,z]],volume; rz: r,z,volume) or HDF5 (.h5: position [N][dim], volume "
         "[N]), relative to the deck.");
}

template <class K> void keysOf(K& k, RadialVelocityConfig& v) {
  k.section("", "A velocity along (x - center)/|x - center| added to every particle of the body.");
  k.vector("center", v.center, required, "m", "", "The point it points away from.");
  k.number("speed", v.speed, required, "m/s", any(),
           "The speed added; negative: towards the centre (Noh's inflow).");
}

template <class K> void keysOf(K& k, CantileverVelocityConfig& v) {
  k.section("", "The first bending mode of a beam clamped at root along +x (Gray, Monaghan & "
                "Swift 2001).");
  k.vector("root", v.root, required, "m", "", "The clamped end; no velocity at x below root's x.");
  k.number("length", v.length, required, "m", above(0), "The beam's length along +x.");
  k.number("tip_speed", v.tip_speed, required, "m/s", any(), "The y velocity of the free end.");
}

template <class K> void keysOf(K& k, LinearVelocityConfig& v) {
  k.section("", "A homogeneous velocity gradient: v += G (x - center).");
  k.vector("center", v.center, required, "m", "", "The point that gets no added velocity.");
  k.matrix("gradient", v.gradient, required, "1/s", "",
           "G, the velocity gradient, by rows: G[i][j] = dv_i/dx_j.");
}

template <class K> void keysOf(K& k, SineVelocityConfig& v) {
  k.section("", "A standing wave's velocity: v += amplitude sin(wavevector . (x - origin)).");
  k.vector("amplitude", v.amplitude, required, "m/s", "", "The velocity at the wave's crest.");
  k.vector("wavevector", v.wavevector, required, "1/m", "", "k, 2 pi over the wavelength.");
  k.vector("origin", v.origin, required, "m", "", "A node of the wave.");
}

template <class K> void keysOf(K& k, JetConfig& j) {
  k.section("", "A discrete jet (Austin 2013, Fig. 5.2): segments made bodies NAME_segmentK.");
  k.other("name", "string", "\"jetK\", K its 1-based index", "", "unique, non-empty, no '.'",
          "Names its segments' bodies; a penetrator may name the whole jet.");
  k.other("file", "string", "required unless segments is given", "", "",
          "A CSV of segment,radius,length,velocity,insert_time, relative to the deck.");
  k.other("segments", "[[float, float, float, float, float]]", "read from file", "",
          "distinct integer ids; radius, length > 0; times >= 0",
          "Rows [segment, radius m, length m, velocity m/s, insert_time s]; as the file holds.");
  k.text("material", j.material, required, "a [[material]]'s name",
         "The material of every segment.");
  k.vector("axis", j.axis, required, "", "not zero; a coordinate axis below 3D",
           "The direction of flight (any length); in rz [0, 1] or [0, -1].");
  k.vector("entry", j.entry, required, "m", "in rz: on the axis",
           "Where each segment's front face is at its insert time.");
  k.number("spacing", j.spacing, required, "m", above(0),
           "The lattice spacing of the segments' particles, divided by run.resolution.");
}

const auto kBox = [](auto& k, ShapeConfig& s) { boxKeys(k, s); };
const auto kSphere = [](auto& k, ShapeConfig& s) { sphereKeys(k, s); };
const auto kCylinder = [](auto& k, ShapeConfig& s) { cylinderKeys(k, s); };
const auto kRing = [](auto& k, ShapeConfig& s) { ringKeys(k, s); };
const auto kCone = [](auto& k, ShapeConfig& s) { coneKeys(k, s); };
const auto kOgive = [](auto& k, ShapeConfig& s) { ogiveKeys(k, s); };
const auto kPolygon = [](auto& k, ShapeConfig& s) { polygonKeys(k, s); };
const auto kUnion = [](auto& k, ShapeConfig& s) { unionKeys(k, s); };
const auto kDifference = [](auto& k, ShapeConfig& s) { differenceKeys(k, s); };
const auto kParticles = [](auto& k, ShapeConfig& s) { particlesKeys(k, s); };
const auto kKeys = [](auto& k, auto& c) -> decltype(keysOf(k, c)) { keysOf(k, c); };

// In geometry 'rz' a round shape is a body of revolution: centred on the axis (a sphere, a
// shell) or clear of it (a torus); one that straddles the axis would be two bodies in one.
void checkAxisymmetric(const deck_detail::TableReader& r, bool rz, double centerR, double radius) {
  if (!rz || centerR == 0.0 || centerR - radius >= 0.0) return;
  r.fail("center", r.quoted("center") + " has r = " + deck_detail::formatNumber(centerR) +
                       ": in geometry 'rz' a round shape is centred on the axis (r = 0) or lies "
                       "clear of it (r - radius >= 0)");
}

} // namespace

std::vector<KeySection> body() {
  return {
      sectionOf<BodyConfig>("body", kKeys),
      {"body.shape",
       "",
       "The region a body fills; particles are the lattice sites inside it.",
       {
           {"type",
            "one of: box, sphere, cylinder, ring, cone, ogive, polygon, union, difference, "
            "particles",
            "required", "", "", "The shape; the other keys are its type's."},
       }},
      sectionOf<ShapeConfig>("body.shape", kBox),
      sectionOf<ShapeConfig>("body.shape", kSphere),
      sectionOf<ShapeConfig>("body.shape", kCylinder),
      sectionOf<ShapeConfig>("body.shape", kRing),
      sectionOf<ShapeConfig>("body.shape", kCone),
      sectionOf<ShapeConfig>("body.shape", kOgive),
      sectionOf<ShapeConfig>("body.shape", kPolygon),
      sectionOf<ShapeConfig>("body.shape", kUnion),
      sectionOf<ShapeConfig>("body.shape", kDifference),
      sectionOf<ShapeConfig>("body.shape", kParticles),
      sectionOf<RadialVelocityConfig>("body.radial_velocity", kKeys),
      sectionOf<CantileverVelocityConfig>("body.cantilever_velocity", kKeys),
      sectionOf<LinearVelocityConfig>("body.linear_velocity", kKeys),
      sectionOf<SineVelocityConfig>("body.sine_velocity", kKeys),
      sectionOf<GradingConfig>("body.grading", kKeys),
      sectionOf<GradingLine>("body.grading.line", kKeys),
      sectionOf<GradingPlane>("body.grading.plane", kKeys),
      sectionOf<JetConfig>("jet", kKeys),
  };
}

void readBody(const deck_detail::TableReader& r, BodyConfig& b, std::size_t dimension) {
  Read read(r, dimension);
  keysOf(read, b);
  if (b.velocity.empty()) b.velocity.assign(dimension, 0.0);
  double speed2 = 0.0;
  for (double v : b.velocity) speed2 += v * v;
  r.check(std::sqrt(speed2) < 299792458.0, "velocity", "slower than light (a speed below 3e8 m/s)",
          std::sqrt(speed2));
}

namespace {

// A body of revolution in rz turns about the z axis: its base on it, its axis along it.
void checkOnAxis(const deck_detail::TableReader& r, bool rz, const ShapeConfig& s) {
  if (!rz) return;
  if (s.base[0] != 0.0)
    r.fail("base", r.quoted("base") + " has r = " + deck_detail::formatNumber(s.base[0]) +
                       ": in geometry 'rz' a cone or an ogive turns about the axis (r = 0)");
  if (s.axis[0] != 0.0)
    r.fail("axis", r.quoted("axis") + " must lie along z in geometry 'rz' ([0, 1] or [0, -1])");
}

// Whether segments pq and uv cross (share a point other than a common end).
bool segmentsCross(const std::vector<double>& p, const std::vector<double>& q,
                   const std::vector<double>& u, const std::vector<double>& v) {
  const auto orient = [](const std::vector<double>& a, const std::vector<double>& b,
                         const std::vector<double>& c) {
    const double o = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    return (o > 0.0) - (o < 0.0);
  };
  const int o1 = orient(p, q, u), o2 = orient(p, q, v), o3 = orient(u, v, p), o4 = orient(u, v, q);
  if (o1 != o2 && o3 != o4 && o1 * o2 <= 0 && o3 * o4 <= 0) {
    // Touching at a shared end is the polygon's own vertex, not a crossing.
    return !(p == u || p == v || q == u || q == v);
  }
  const auto onSegment = [](const std::vector<double>& a, const std::vector<double>& b,
                            const std::vector<double>& c) { // c on ab, given collinear
    return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) &&
           std::min(a[1], b[1]) <= c[1] && c[1] <= std::max(a[1], b[1]);
  };
  // Collinear overlaps: an edge folded back on another.
  if (o1 == 0 && o2 == 0)
    return (onSegment(p, q, u) && u != p && u != q) || (onSegment(p, q, v) && v != p && v != q) ||
           (onSegment(u, v, p) && p != u && p != v);
  return false;
}

void readPolygon(const deck_detail::TableReader& r, ShapeConfig& s, std::size_t dimension,
                 bool rz) {
  using deck_detail::formatNumber;
  s.points = r.required(r.points("points", dimension), "points");
  const std::size_t n = s.points.size();
  if (n < 3)
    r.fail("points", r.quoted("points") + " needs 3 or more vertices, got " + std::to_string(n));
  double area = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto& p = s.points[k];
    const auto& q = s.points[(k + 1) % n];
    area += p[0] * q[1] - q[0] * p[1];
    if (rz && p[0] < 0.0)
      r.fail("points", r.quoted("points") + " vertex " + std::to_string(k + 1) + " has r = " +
                           formatNumber(p[0]) + " < 0: in geometry 'rz' x is the radius");
  }
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      const bool adjacent = b == a + 1 || (a == 0 && b == n - 1);
      if (adjacent) continue; // they share a vertex by construction
      if (segmentsCross(s.points[a], s.points[(a + 1) % n], s.points[b], s.points[(b + 1) % n]))
        r.fail("points", r.quoted("points") + " edges " + std::to_string(a + 1) + " and " +
                             std::to_string(b + 1) +
                             " cross: a polygon's edges meet only at their vertices (a union or "
                             "difference of polygons makes other regions)");
    }
  if (!(std::abs(area) > 0.0))
    r.fail("points", r.quoted("points") + " encloses no area (its vertices lie on a line)");
}

// A nested shape's reader: the table at `node`, named as the `index`th (0-based) of `key`, or
// as `key` itself.
deck_detail::TableReader partReader(const deck_detail::TableReader& r, const toml::table& t,
                                    std::string_view key, std::optional<std::size_t> index) {
  return {t, index ? r.context().item(key, *index) : r.context().child(key), r.deckPath(),
          r.notes()};
}

void readParts(const deck_detail::TableReader& r, const char* key, std::size_t atLeastCount,
               ShapeConfig& s, std::size_t dimension, bool rz) {
  const auto tables = r.tables(key);
  if (tables.size() < atLeastCount)
    r.fail(key, r.quoted(key) + " needs " + std::to_string(atLeastCount) + " or more shapes, got " +
                    std::to_string(tables.size()));
  for (std::size_t k = 0; k < tables.size(); ++k) {
    readShape(partReader(r, *tables[k], key, k), s.parts.emplace_back(), dimension, rz);
    if (s.parts.back().type == ShapeType::Particles)
      r.fail(key, r.quoted(key) + " holds a 'particles' shape: a file's particles are a body "
                                  "of their own (join or cut lattice shapes only)");
  }
}

} // namespace

void readShape(const deck_detail::TableReader& r, ShapeConfig& s, std::size_t dimension, bool rz) {
  using deck_detail::formatNumber;
  s.where = r.where();
  const std::string type = r.choice("type", deck_detail::typeNames("body.shape"), std::nullopt);
  s.type = kShapeNames.at(type);
  const std::string dims = "; run.dimension is " + std::to_string(dimension) + ")";
  if (s.type == ShapeType::Cylinder && dimension != 3)
    r.fail("type", "shape 'cylinder' is 3D only (use 'sphere' or 'box' in 1D and 2D" + dims);
  if (s.type == ShapeType::Ring && dimension != 2)
    r.fail("type", "shape 'ring' is 2D only (use 'sphere' or 'box' in 1D and 3D" + dims);
  if ((s.type == ShapeType::Cone || s.type == ShapeType::Ogive) && dimension == 1)
    r.fail("type", "shape '" + type + "' needs 2D, rz or 3D (in 1D a 'box'" + dims);
  if (s.type == ShapeType::Polygon && dimension != 2)
    r.fail("type", "shape 'polygon' is 2D and rz only (in 3D a 'union' or 'difference' of "
                   "shapes, or 'particles' from a mesher" +
                       dims);
  deck_detail::allowTypedKeys(r, "body.shape", type, "shape");
  Read read(r, dimension);
  switch (s.type) {
  case ShapeType::Box:
    kBox(read, s);
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
    kSphere(read, s);
    checkAxisymmetric(r, rz, s.center[0], s.radius);
    break;
  case ShapeType::Cylinder:
    kCylinder(read, s);
    if (deck_detail::norm(s.axis) == 0.0)
      r.fail("axis", r.quoted("axis") + " must not be the zero vector");
    break;
  case ShapeType::Ring:
    kRing(read, s);
    checkAxisymmetric(r, rz, s.center[0], s.outer_radius);
    break;
  case ShapeType::Cone:
  case ShapeType::Ogive:
    if (s.type == ShapeType::Cone)
      kCone(read, s);
    else
      kOgive(read, s);
    if (deck_detail::norm(s.axis) == 0.0)
      r.fail("axis", r.quoted("axis") + " must not be the zero vector");
    checkOnAxis(r, rz, s);
    break;
  case ShapeType::Polygon:
    readPolygon(r, s, dimension, rz);
    break;
  case ShapeType::Union:
    readParts(r, "shapes", 2, s, dimension, rz);
    break;
  case ShapeType::Difference: {
    const toml::table* from = r.subtable("from");
    if (!from) r.missing("from");
    readShape(partReader(r, *from, "from", std::nullopt), s.parts.emplace_back(), dimension, rz);
    if (s.parts.back().type == ShapeType::Particles)
      r.fail("from", r.quoted("from") + " is a 'particles' shape: a file's particles are a body "
                                        "of their own (cut lattice shapes only)");
    readParts(r, "minus", 1, s, dimension, rz);
    break;
  }
  case ShapeType::Particles: {
    kParticles(read, s);
    // Relative to the deck, as a jet's file; the deck as run names it absolutely, so that it is
    // found from wherever that deck is read again.
    namespace fs = std::filesystem;
    fs::path path(s.file);
    if (path.is_relative()) path = fs::path(r.deckPath()).parent_path() / path;
    std::error_code ec;
    path = fs::absolute(path, ec).lexically_normal();
    if (ec || !fs::exists(path, ec))
      r.fail("file", r.quoted("file") + " names no file: " + path.string());
    s.cloud = std::make_shared<const ParticleCloud>(readParticleFile(path.string(), dimension, rz));
    std::ostringstream text;
    text << toml::value<std::string>(path.string());
    r.noteResolved("file", text.str());
    break;
  }
  }
}

namespace {

// Key `key`'s inline table of `r` into `field`, read against its section, if present; then
// `check(reader, field)` with the table's own reader (errors point into it).
template <class T, class Check>
void readSubtable(const deck_detail::TableReader& r, const char* key, const std::string& section,
                  std::size_t dimension, std::optional<T>& field, Check&& check) {
  const toml::table* t = r.subtable(key);
  if (!t) return;
  const deck_detail::TableReader sub(*t, r.context().child(key), r.deckPath(), r.notes());
  sub.allowOnly(*deck_detail::schemaKeys(section));
  Read visit(sub, dimension);
  keysOf(visit, field.emplace());
  check(sub, *field);
}

const auto kNoCheck = [](const deck_detail::TableReader&, const auto&) {};

// A reference's direction: `v`, key `key` of `sub`, made a unit vector.
void makeUnit(const deck_detail::TableReader& sub, const char* key, std::vector<double>& v) {
  const double n = deck_detail::norm(v);
  if (n == 0.0) sub.fail(key, sub.quoted(key) + " must not be the zero vector");
  for (double& x : v) x /= n;
}

} // namespace

void readVelocityFields(const deck_detail::TableReader& r, std::size_t dimension, BodyConfig& b) {
  const auto read = [&](const char* key, auto& field) {
    readSubtable(r, key, std::string("body.") + key, dimension, field, kNoCheck);
  };
  read("radial_velocity", b.radial_velocity);
  if (r.has("cantilever_velocity") && dimension < 2)
    r.fail("cantilever_velocity",
           r.quoted("cantilever_velocity") + " needs run.dimension 2 or 3 (a transverse velocity)");
  read("cantilever_velocity", b.cantilever_velocity);
  read("linear_velocity", b.linear_velocity);
  read("sine_velocity", b.sine_velocity);
}

void readGrading(const deck_detail::TableReader& r, std::size_t dimension, BodyConfig& b) {
  readSubtable(r, "grading", "body.grading", dimension, b.grading,
               [&](const deck_detail::TableReader& g, GradingConfig& c) {
                 c.where = r.whereValue("grading");
                 if (g.has("line") && dimension == 1)
                   g.fail("line", g.quoted("line") +
                                      " needs run.dimension 2 or 3 (in 1D a point or a plane)");
                 readSubtable(g, "line", "body.grading.line", dimension, c.line,
                              [](const deck_detail::TableReader& sub, GradingLine& l) {
                                makeUnit(sub, "direction", l.direction);
                              });
                 readSubtable(g, "plane", "body.grading.plane", dimension, c.plane,
                              [](const deck_detail::TableReader& sub, GradingPlane& p) {
                                makeUnit(sub, "normal", p.normal);
                              });
                 const int given = (c.point.empty() ? 0 : 1) + (c.line ? 1 : 0) + (c.plane ? 1 : 0);
                 if (given != 1)
                   r.fail("grading", r.quoted("grading") +
                                         " needs exactly one reference, point = [...], line = "
                                         "{point, direction} or plane = {point, normal} (" +
                                         std::to_string(given) + " given)");
                 if (c.max_spacing < b.spacing)
                   g.fail("max_spacing", g.quoted("max_spacing") + " is " +
                                             deck_detail::formatNumber(c.max_spacing) +
                                             " m, below the body's spacing " +
                                             deck_detail::formatNumber(b.spacing) +
                                             " m (the finest spacing)");
               });
}

JetConfig readJet(const deck_detail::TableReader& r, std::size_t dimension) {
  r.allowOnly(*deck_detail::schemaKeys("jet"));
  JetConfig j;
  Read read(r, dimension);
  keysOf(read, j);
  return j;
}

} // namespace spall::io::keys
