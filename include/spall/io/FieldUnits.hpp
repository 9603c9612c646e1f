#pragma once
// The SI unit of every field a snapshot can hold, as the `units` attribute writes it ("1": a
// pure number). Extensive fields follow the geometry: 1D is per unit area of the plane (mass in
// kg/m^2), plane strain per unit depth (kg/m), rz a full ring (kg) and 3D a volume.
#include <string>
#include <string_view>

namespace spall::io {

// The snapshot's geometry attribute: "1d", "plane", "rz", "3d".
std::string geometryName(int dimension, bool rz);
// The position's components as the snapshot's `axes` attribute: "x", "x y", "r z", "x y z".
std::string axesName(int dimension, bool rz);

// Empty for a name it does not know (a test runs every model's fields against it).
std::string fieldUnit(std::string_view name, int dimension, bool rz);

} // namespace spall::io
