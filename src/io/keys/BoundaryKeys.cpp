// [[boundary]] by type and [[energy_source]] (read in io/Deck.cpp, io/DeckPressureTable.cpp).
#include "spall/io/DeckKeys.hpp"

namespace spall::io::keys {

std::vector<KeySection> boundaries() {
  return {
      {"boundary",
       "",
       "A boundary condition; entries without a name are addressed as boundary.1, boundary.2, ...",
       {
           {"type", "one of: rigid_wall, periodic, pressure", "required", "", "",
            "The boundary; the other keys are its type's (mpm: rigid_wall and pressure only)."},
       }},
      {"boundary",
       "rigid_wall",
       "A plane mirror: particles behind it are folded back; in rz along r or z only.",
       {
           {"point", "float[dim]", "required", "m", "in rz, a wall along r: r > 0",
            "A point on the wall."},
           {"normal", "float[dim]", "required", "", "not zero; in rz along r or z",
            "The normal, pointing into the material (any length)."},
       }},
      {"boundary",
       "periodic",
       "A periodic axis: what leaves at max enters at min; in rz along z only.",
       {
           {"axis", "integer", "required", "", "0 to dimension - 1; in rz: 1",
            "The periodic axis: 0 x, 1 y, 2 z."},
           {"min", "float", "required", "m", "", "The lower end of the period."},
           {"max", "float", "required", "m", "> min", "The upper end of the period."},
       }},
      {"boundary",
       "pressure",
       "A confining pressure on a body's surface, a table in time; one per body.",
       {
           {"body", "string", "required", "", "a [[body]]'s name", "The body it loads."},
           {"pressure", "[[float, float]]", "required", "s, Pa",
            "one row or more; times >= 0 and rising",
            "Rows [time, pressure], linear between; held before the first and after the last."},
       }},
      {"energy_source",
       "",
       "Energy deposited at t = 0 in a sphere about a point (blast waves: Sedov).",
       {
           {"center", "float[dim]", "required", "m", "", "The centre of the deposit."},
           {"radius", "float", "0.0", "m", ">= 0",
            "Support of a cubic-spline weight; 0: all to the particle nearest the centre."},
           {"energy", "float", "required", "J", ">= 0", "The total energy added."},
       }},
  };
}

} // namespace spall::io::keys
