#include "spall/io/FieldUnits.hpp"

#include <array>
#include <utility>

namespace spall::io {

std::string geometryName(int dimension, bool rz) {
  if (rz) return "rz";
  return dimension == 1 ? "1d" : dimension == 2 ? "plane" : "3d";
}

std::string axesName(int dimension, bool rz) {
  if (rz) return "r z";
  return dimension == 1 ? "x" : dimension == 2 ? "x y" : "x y z";
}

std::string fieldUnit(std::string_view name, int dimension, bool rz) {
  // A particle's mass and the force on a node: per unit area in 1D, per unit depth in plane
  // strain; the confining load's area vector: 1 in 1D, a length in plane strain, an area else.
  const bool ring = rz || dimension == 3;
  if (name == "mass") return ring ? "kg" : dimension == 2 ? "kg/m" : "kg/m^2";
  if (name == "force") return ring ? "N" : dimension == 2 ? "N/m" : "N/m^2";
  if (name == "surface_area") return ring ? "m^2" : dimension == 2 ? "m" : "1";
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 42> kUnits{{
      {"id", "1"},
      {"position", "m"},
      {"velocity", "m/s"},
      {"density", "kg/m^3"},
      {"pressure", "Pa"},
      {"specific_internal_energy", "J/kg"},
      {"sound_speed", "m/s"},
      {"smoothing", "1/m"}, // H, the inverse smoothing length (tensor)
      {"smoothing_length", "m"},
      {"stress", "Pa"},
      {"stress_hoop", "Pa"},
      {"deviatoric_stress", "Pa"},
      {"material", "1"},
      {"body", "1"},
      {"plastic_strain", "1"},
      {"temperature", "K"},
      {"damage", "1"},
      {"damage_tensor", "1"},
      {"flaw_count", "1"},
      {"flaws_active", "1"},
      {"next_flaw_strain", "1"},
      {"porosity_alpha", "1"},
      {"plastic_distension", "1"},
      {"porosity", "1"},
      {"plastic_volumetric_strain", "1"},
      {"cap_position", "Pa"}, // X, in the units of I1
      {"pore_pressure", "Pa"},
      {"cap_overstress", "Pa"},
      {"cap_overstress_i1", "Pa"},
      {"deformation_gradient", "1"},
      {"velocity_gradient", "1/s"},
      {"fragment", "1"},
      {"confining_pressure", "Pa"},
      {"contact_group", "1"},
      {"particle_half_width", "m"},
      {"particle_domain", "m"},
      {"viscous_pressure", "Pa"},
      {"affine_velocity", "1/s"}, // the APIC/MLS C_p, a velocity gradient
      {"kernel_correction", "1"},
      {"index", "1"},  // a grid node's lattice index
      {"fields", "1"}, // a grid node's count of velocity fields
      {"acceleration", "m/s^2"},
  }};
  for (const auto& [n, u] : kUnits)
    if (n == name) return std::string(u);
  return {};
}

} // namespace spall::io
