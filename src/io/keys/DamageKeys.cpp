// A material's damage model, material.damage, by type (read in io/DeckMaterial.cpp).
#include "spall/io/DeckKeys.hpp"

namespace spall::io::keys {

std::vector<KeySection> damage() {
  return {
      {"material.damage",
       "",
       "Damage D in [0, 1] that degrades the stress; needs a strength model, not cap.",
       {
           {"type", "one of: grady_kipp, johnson_cook", "required", "", "",
            "The damage model; the other keys are its type's."},
       }},
      {"material.damage",
       "grady_kipp",
       "Tensile flaws of a Weibull law that grow cracks (Grady & Kipp; Benz & Asphaug 1994, 1995).",
       {
           {"weibull_k", "float", "required", "1/m^3", "> 0",
            "k of the Weibull law n(eps) = k eps^m: flaws per unit volume at unit strain."},
           {"weibull_m", "float", "required", "", "> 0", "m, the Weibull exponent."},
           {"crack_speed", "float", "0.4", "", "(0, 1]",
            "The crack growth speed over the longitudinal sound speed."},
           {"mode", "one of: scalar, tensor", "\"scalar\"", "", "",
            "scalar: one damage per particle; tensor: one per principal direction (Owen 2010)."},
       }},
      {"material.damage",
       "johnson_cook",
       "Johnson & Cook (1985), Austin (2013) Eq. 6.5: dD = d eps_p / eps_f; needs plastic strain.",
       {
           {"D1", "float", "required", "", "",
            "D1 of eps_f = [D1 + D2 exp(D3 sigma*)][1 + D4 ln rate*][1 + D5 T*]."},
           {"D2", "float", "required", "", "", "D2, the triaxiality term's coefficient."},
           {"D3", "float", "required", "", "",
            "D3, the triaxiality exponent (sigma* = -p / sigma_eq)."},
           {"D4", "float", "required", "", "", "D4, the strain rate coefficient."},
           {"D5", "float", "required", "", "", "D5, the temperature coefficient."},
           {"reference_strain_rate", "float", "required", "1/s", "> 0",
            "The plastic strain rate below which the rate term is 1."},
           {"room_temperature", "float", "required", "K", "> 0", "T* = 0 of the temperature term."},
           {"melt_temperature", "float", "required", "K", "> room_temperature",
            "T* = 1 of the temperature term."},
       }},
  };
}

} // namespace spall::io::keys
