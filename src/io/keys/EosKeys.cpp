// A material's equation of state, material.eos, by type (read in io/DeckMaterial.cpp).
#include "spall/io/DeckKeys.hpp"

namespace spall::io::keys {

std::vector<KeySection> eos() {
  return {
      {"material.eos",
       "",
       "Pressure and sound speed from density and specific energy; every material but cap's.",
       {
           {"type", "one of: ideal_gas, linear, mie_gruneisen, tillotson", "required", "", "",
            "The equation of state; the other keys are its type's."},
       }},
      {"material.eos",
       "ideal_gas",
       "p = (gamma - 1) rho e.",
       {
           {"gamma", "float", "required", "", "> 1", "The ratio of specific heats."},
       }},
      {"material.eos",
       "linear",
       "p = K (rho/rho0 - 1): a barotropic solid or liquid; the energy plays no part.",
       {
           {"bulk_modulus", "float", "required", "Pa", "> 0", "K, the bulk modulus."},
           {"min_pressure", "float", "none", "Pa", "<= 0",
            "The tension limit: the pressure never falls below it (a spall cutoff)."},
       }},
      {"material.eos",
       "mie_gruneisen",
       "Mie-Gruneisen on a linear Us-up Hugoniot (Lam, Shen & Gong 2001, Eqs. 4-6).",
       {
           {"c0", "float", "required", "m/s", "> 0", "C0, the bulk sound speed: Us at up = 0."},
           {"s", "float", "required", "", "", "S, the slope of the Us-up Hugoniot."},
           {"gamma0", "float", "required", "", "", "Gamma0, the Gruneisen coefficient at rho0."},
           {"min_pressure", "float", "none", "Pa", "<= 0",
            "The tension limit: the pressure never falls below it (a spall cutoff)."},
       }},
      {"material.eos",
       "tillotson",
       "Tillotson (1962), as used for planetary impacts (Melosh 1989, Sec. 3.5).",
       {
           {"a", "float", "required", "", ">= 0", "a of the energy term (a + b/w) rho e."},
           {"b", "float", "required", "", ">= 0", "b of the energy term (a + b/w) rho e."},
           {"A", "float", "required", "Pa", "> 0", "A, the linear compression term A mu."},
           {"B", "float", "required", "Pa", "", "B, the quadratic compression term B mu^2."},
           {"alpha", "float", "required", "", ">= 0",
            "alpha of the hot expanded decay exp(-alpha (1/eta - 1)^2)."},
           {"beta", "float", "required", "", ">= 0",
            "beta of the hot expanded A mu exp(-beta (1/eta - 1))."},
           {"e0", "float", "required", "J/kg", "> 0",
            "E0, the energy scale of w = e/(E0 eta^2) + 1."},
           {"e_iv", "float", "required", "J/kg", "> 0",
            "E_iv, the energy of incipient vaporisation."},
           {"e_cv", "float", "required", "J/kg", "> e_iv",
            "E_cv, the energy of complete vaporisation."},
           {"min_pressure", "float", "none", "Pa", "<= 0",
            "The tension limit: the pressure never falls below it (a spall cutoff)."},
       }},
  };
}

} // namespace spall::io::keys
