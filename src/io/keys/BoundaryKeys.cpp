// [[boundary]] by type and [[energy_source]]: the rows and reads (Keys.hpp); io/Deck.cpp checks
// the body a pressure names and the geometry of walls, io/DeckPressureTable.cpp reads the table.
#include "Keys.hpp"

namespace spall::io::keys {

namespace {

template <class K> void rigidWallKeys(K& k, BoundaryConfig& b) {
  k.section("rigid_wall",
            "A plane mirror: particles behind it are folded back; in rz along r or z only.");
  k.vector("point", b.point, required, "m", "in rz, a wall along r: r > 0", "A point on the wall.");
  k.vector("normal", b.normal, required, "", "not zero; in rz along r or z",
           "The normal, pointing into the material (any length).");
  k.number("friction", b.friction, keep, "", atLeast(0),
           "MPM: Coulomb's coefficient mu against the material pressed on it; 0: it slips.");
}

// `dimension`, `rz`: run.dimension and run.geometry = "rz", which bound the axis.
template <class K> void periodicKeys(K& k, BoundaryConfig& b, double dimension, bool rz) {
  k.section("periodic", "A periodic axis: what leaves at max enters at min; in rz along z only.");
  const double last = dimension - 1.0;
  k.integer("axis", b.axis, required, "", within(0, "dimension - 1", last),
            "The periodic axis: 0 x, 1 y, 2 z.");
  k.require("axis", "in rz: 1", !rz || b.axis == 1,
            "of a periodic boundary in geometry 'rz' is 1 (along z): r is bounded by the axis");
  k.number("min", b.min, required, "m", any(), "The lower end of the period.");
  k.number("max", b.max, required, "m", above("min", b.min), "The upper end of the period.");
}

template <class K> void pressureKeys(K& k, BoundaryConfig& b) {
  k.section("pressure", "A confining pressure on a body's surface, a table in time; one per body.");
  k.text("body", b.body, required, "a [[body]]'s name", "The body it loads.");
  k.other("pressure", "[[float, float]]", "required", "s, Pa",
          "one row or more; times >= 0 and rising",
          "Rows [time, pressure], linear between; held before the first and after the last.");
}

template <class K> void keysOf(K& k, EnergySourceConfig& e) {
  k.section("", "Energy deposited at t = 0 in a sphere about a point (blast waves: Sedov).");
  k.vector("center", e.center, required, "m", "", "The centre of the deposit.");
  k.number("radius", e.radius, keep, "m", atLeast(0),
           "Support of a cubic-spline weight; 0: all to the particle nearest the centre.");
  k.number("energy", e.energy, required, "J", atLeast(0), "The total energy added.");
}

const auto kRigidWall = [](auto& k, BoundaryConfig& b) { rigidWallKeys(k, b); };
const auto kPressure = [](auto& k, BoundaryConfig& b) { pressureKeys(k, b); };
const auto kKeys = [](auto& k, auto& c) -> decltype(keysOf(k, c)) { keysOf(k, c); };

} // namespace

std::vector<KeySection> boundaries() {
  return {
      {"boundary",
       "",
       "A boundary condition; entries without a name are addressed as boundary.1, boundary.2, ...",
       {
           {"type", "one of: rigid_wall, periodic, pressure", "required", "", "",
            "The boundary; the other keys are its type's (mpm: rigid_wall and pressure only)."},
       }},
      sectionOf<BoundaryConfig>("boundary", kRigidWall),
      sectionOf<BoundaryConfig>("boundary",
                                [](auto& k, auto& b) { periodicKeys(k, b, 3.0, false); }),
      sectionOf<BoundaryConfig>("boundary", kPressure),
      sectionOf<EnergySourceConfig>("energy_source", kKeys),
  };
}

void readBoundary(const deck_detail::TableReader& r, BoundaryConfig& b, std::size_t dimension,
                  bool rz) {
  b.where = r.where();
  b.type = deck_detail::readType(r, "boundary", kBoundaryTypeNames, "boundary");
  Read read(r, dimension);
  switch (b.type) {
  case BoundaryType::RigidWall:
    kRigidWall(read, b);
    break;
  case BoundaryType::Periodic:
    periodicKeys(read, b, static_cast<double>(dimension), rz);
    break;
  case BoundaryType::Pressure:
    kPressure(read, b);
    b.pressure = deck_detail::readPressureTable(r);
    break;
  }
}

void readEnergySource(const deck_detail::TableReader& r, EnergySourceConfig& e,
                      std::size_t dimension) {
  r.allowOnly(*deck_detail::schemaKeys("energy_source"));
  e.where = r.where();
  Read read(r, dimension);
  keysOf(read, e);
}

} // namespace spall::io::keys
