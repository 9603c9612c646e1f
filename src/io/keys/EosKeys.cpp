// A material's equation of state, material.eos, by type: the reference's rows and the reader's
// reads (Keys.hpp), one function per model of materials/Eos.hpp. Each model's rho0 is the
// material's density (set by the reader, io/DeckMaterial.cpp).
#include "Keys.hpp"

namespace spall::io::keys {

namespace {

constexpr std::string_view kPath = "material.eos";

template <class K> void tensionLimit(K& k, double& minPressure) {
  k.number("min_pressure", minPressure, off, "Pa", atMost(0),
           "The tension limit: the pressure never falls below it (a spall cutoff).");
}

template <class K> void keysOf(K& k, materials::IdealGas& p, double&) {
  k.section("ideal_gas", "p = (gamma - 1) rho e.");
  k.number("gamma", p.gamma, required, "", above(1), "The ratio of specific heats.");
}

template <class K> void keysOf(K& k, materials::LinearEos& p, double& minPressure) {
  k.section("linear",
            "p = K (rho/rho0 - 1): a barotropic solid or liquid; the energy plays no part.");
  k.number("bulk_modulus", p.K, required, "Pa", modulus(above(0)), "K, the bulk modulus.");
  tensionLimit(k, minPressure);
}

template <class K> void keysOf(K& k, materials::MieGruneisen& p, double& minPressure) {
  k.section("mie_gruneisen",
            "Mie-Gruneisen on a linear Us-up Hugoniot (Lam, Shen & Gong 2001, Eqs. 4-6).");
  k.number("c0", p.C0, required, "m/s", soundSpeed(above(0)),
           "C0, the bulk sound speed: Us at up = 0.");
  // A slope <= 0 would slow the shock as it strengthens; a negative Gruneisen coefficient (a
  // material that contracts as it heats) is outside what the linear Us-up form describes.
  k.number("s", p.S, required, "", above(0), "S, the slope of the Us-up Hugoniot.");
  k.number("gamma0", p.Gamma0, required, "", atLeast(0),
           "Gamma0, the Gruneisen coefficient at rho0.");
  tensionLimit(k, minPressure);
}

template <class K> void keysOf(K& k, materials::Tillotson& p, double& minPressure) {
  k.section("tillotson",
            "Tillotson (1962), as used for planetary impacts (Melosh 1989, Sec. 3.5).");
  k.number("a", p.a, required, "", atLeast(0), "a of the energy term (a + b/w) rho e.");
  k.number("b", p.b, required, "", atLeast(0), "b of the energy term (a + b/w) rho e.");
  k.number("A", p.A, required, "Pa", modulus(above(0)), "A, the linear compression term A mu.");
  // Tillotson's and Melosh's tables have B > 0 for every material: compression stiffens.
  k.number("B", p.B, required, "Pa", atLeast(0), "B, the quadratic compression term B mu^2.");
  k.number("alpha", p.alpha, required, "", atLeast(0),
           "alpha of the hot expanded decay exp(-alpha (1/eta - 1)^2).");
  k.number("beta", p.beta, required, "", atLeast(0),
           "beta of the hot expanded A mu exp(-beta (1/eta - 1)).");
  k.number("e0", p.E0, required, "J/kg", above(0), "E0, the energy scale of w = e/(E0 eta^2) + 1.");
  k.number("e_iv", p.Eiv, required, "J/kg", above(0),
           "E_iv, the energy of incipient vaporisation.");
  k.number("e_cv", p.Ecv, required, "J/kg", above("e_iv", p.Eiv),
           "E_cv, the energy of complete vaporisation.");
  tensionLimit(k, minPressure);
}

// The describing passes give the tension limit a scratch place; reading gives the config's.
struct Keys {
  double* minPressure;
  template <class K, class M>
  auto operator()(K& k, M& p) const -> decltype(keysOf(k, p, *minPressure)) {
    keysOf(k, p, *minPressure);
  }
};

} // namespace

std::vector<KeySection> eos() {
  double scratch = 0.0;
  return describeTypes<materials::Eos>(
      kPath, "Pressure and sound speed from density and specific energy; every material but cap's.",
      "The equation of state; the other keys are its type's.", Keys{&scratch});
}

materials::Eos readEos(const deck_detail::TableReader& r, std::string_view type,
                       double& minPressure) {
  return readType<materials::Eos>(r, kPath, type, Keys{&minPressure});
}

} // namespace spall::io::keys

std::string_view spall::eosTypeName(const EosConfig& c) {
  double scratch = 0.0;
  return io::keys::typeName(c.model, io::keys::kPath, io::keys::Keys{&scratch});
}
