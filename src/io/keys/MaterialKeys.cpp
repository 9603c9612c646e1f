// [[material]] itself: its name, density and models (read in io/DeckMaterial.cpp).
#include "spall/io/DeckKeys.hpp"

namespace spall::io::keys {

std::vector<KeySection> material() {
  return {
      {"material",
       "",
       "A material: its reference density and its models, each a table with a type.",
       {
           {"name", "string", "required", "", "unique, non-empty, no '.'",
            "What bodies and jets call it by; --set addresses it as material.NAME."},
           {"density", "float", "required", "kg/m^3", "> 0",
            "rho0, the reference density (a porous material's: its matrix's)."},
           {"eos", "table", "required unless strength is cap", "", "not with a cap strength",
            "The equation of state: {type = ..., ...}."},
           {"strength", "table", "none", "", "",
            "The strength model: {type = ..., ...}; none: a fluid."},
           {"damage", "table", "none", "", "needs a strength model, not cap",
            "The damage model: {type = ..., ...}."},
           {"erosion", "one of: none, no_tension, no_shear, zero_stress", "\"none\"", "",
            "needs damage, but \"none\"",
            "What a fully damaged particle carries (Austin 2013, Sec. 6.4, Eqs. 6.11-6.14)."},
           {"porosity", "table", "none", "", "not with a cap strength",
            "The porosity model: {type = \"p_alpha\", ...}."},
       }},
  };
}

} // namespace spall::io::keys
