#pragma once
// What a fully damaged particle can carry (Austin 2013, Sec. 6.4; materials/Damage.hpp).
#include "spall/core/NameTable.hpp"

namespace spall::materials {

enum class Erosion { None, NoTension, NoShear, ZeroStress };
inline constexpr NameTable<Erosion, 4> kErosionNames{{{{Erosion::None, "none"},
                                                       {Erosion::NoTension, "no_tension"},
                                                       {Erosion::NoShear, "no_shear"},
                                                       {Erosion::ZeroStress, "zero_stress"}}}};

} // namespace spall::materials
