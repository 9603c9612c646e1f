// A material's porosity model, material.porosity, by type (read in io/DeckMaterial.cpp).
#include "spall/io/DeckKeys.hpp"

namespace spall::io::keys {

std::vector<KeySection> porosity() {
  return {
      {"material.porosity",
       "",
       "Sub-resolution porosity around the material's eos; not with a cap strength.",
       {
           {"type", "one of: p_alpha", "required", "", "",
            "The porosity model; the other keys are its type's."},
       }},
      {"material.porosity",
       "p_alpha",
       "P-alpha: the distension on an irreversible crush curve (Herrmann 1969; Jutzi et al. 2008).",
       {
           {"alpha0", "float", "required", "", ">= 1",
            "Initial distension, solid over bulk density: the body starts at density / alpha0."},
           {"elastic_pressure", "float", "required", "Pa", ">= 0",
            "Pe: below it the pores do not crush."},
           {"solid_pressure", "float", "required", "Pa", "> elastic_pressure",
            "Ps: at it the material is fully compacted (alpha = 1)."},
           {"exponent", "float", "2.0", "", "> 0",
            "n of the crush curve 1 + (alpha0 - 1) ((Ps - P)/(Ps - Pe))^n (of its last stage)."},
           {"transition_pressure", "float", "none", "Pa",
            "between elastic_pressure and solid_pressure",
            "Pt of a two-stage curve; with alpha_transition and exponent_transition, all or none."},
           {"alpha_transition", "float", "none", "", "(1, alpha0)",
            "alpha_t, the distension at transition_pressure (two stages)."},
           {"exponent_transition", "float", "none", "", "> 0",
            "n_t, the exponent of the first stage, alpha0 to alpha_t (two stages)."},
           {"elastic_sound_speed", "float", "none", "m/s", "> 0; needs alpha0 > 1",
            "c_e, the porous material's elastic wave speed at alpha0 (Jutzi et al. 2008)."},
       }},
  };
}

} // namespace spall::io::keys
