// A material's strength model, material.strength, by type: the reference's rows and the reader's
// reads (Keys.hpp), one function per model of materials/Strength.hpp and CapPlasticity.hpp.
#include "Keys.hpp"

namespace spall::io::keys {

namespace {

constexpr std::string_view kPath = "material.strength";

// strain_rate: the rate of Johnson-Cook's rate term (plasticRate true: the plastic one).
constexpr NameTable<bool, 2> kStrainRates{{{{true, "plastic"}, {false, "total"}}}};

template <class K> void shearModulus(K& k, double& G) {
  k.number("shear_modulus", G, required, "Pa", modulus(above(0)), "G, the shear modulus.");
}

// The keys of a model that heats by its plastic work (after the starting temperature).
template <class K> void heating(K& k, double& cp, double& chi) {
  k.number("specific_heat", cp, required, "J/(kg K)", specificHeat(above(0)),
           "c_p of the plastic heating dT = chi Y d eps_p / (rho c_p) (Austin 2013, Eq. 6.7).");
  k.number("taylor_quinney", chi, required, "", within(0, 1),
           "chi, the share of the plastic work that heats (Taylor-Quinney).");
}

template <class K> void keysOf(K& k, NoStrength&) {
  k.section("none", "No deviatoric stress: a fluid.");
}

template <class K> void keysOf(K& k, materials::Elastic& p) {
  k.section("elastic", "Hypoelastic shear by the Jaumann rate, never yielding.");
  shearModulus(k, p.G);
}

template <class K> void keysOf(K& k, materials::VonMises& p) {
  k.section("von_mises",
            "Perfect plasticity: radial return to a fixed von Mises (J2) yield stress.");
  shearModulus(k, p.G);
  k.number("yield_stress", p.Y, required, "Pa", strength(above(0)),
           "Y, the von Mises yield stress.");
}

template <class K> void keysOf(K& k, materials::JohnsonCook& p) {
  k.section("johnson_cook",
            "sigma_y = (A + B eps_p^n)(1 + C ln rate*)(1 - T*^m) (Johnson & Cook 1983).");
  shearModulus(k, p.G);
  k.number("A", p.A, required, "Pa", strength(above(0)),
           "A, the yield stress at zero plastic strain.");
  k.number("B", p.B, required, "Pa", strength(atLeast(0)), "B, the strain hardening coefficient.");
  k.number("n", p.n, required, "", above(0), "n, the strain hardening exponent.");
  k.number("C", p.C, required, "", atLeast(0), "C, the strain rate coefficient.");
  k.number("m", p.m, required, "", above(0), "m, the thermal softening exponent.");
  k.number("reference_strain_rate", p.rate0, required, "1/s", above(0),
           "The rate below which the rate term is 1.");
  k.number("room_temperature", p.Troom, required, "K", temperature(above(0)),
           "The starting temperature (absolute), where T* = 0.");
  k.number("melt_temperature", p.Tmelt, required, "K",
           temperature(above("room_temperature", p.Troom)),
           "T* = 1: at and above it the material carries no shear.");
  heating(k, p.cp, p.chi);
  k.choice("strain_rate", p.plasticRate, kStrainRates, true,
           "The rate of the rate term: equivalent plastic (as the paper) or total deviatoric.");
}

template <class K> void keysOf(K& k, materials::ZerilliArmstrong& p) {
  k.section("zerilli_armstrong", "Zerilli & Armstrong (1987): C0 + (C1 + C2 eps^0.5) exp(-C3 T + "
                                 "C4 T ln rate*) + C5 eps^n.");
  shearModulus(k, p.G);
  // Each constant 0 by default: an fcc metal sets C0, C2, C3, C4; a bcc one C0, C1, C3, C4, C5, n.
  k.number("C0", p.C0, 0.0, "Pa", strength(atLeast(0)),
           "C0, the athermal stress and grain-size term.");
  k.number("C1", p.C1, 0.0, "Pa", strength(atLeast(0)),
           "C1, the thermally activated stress (bcc metals).");
  k.number("C2", p.C2, 0.0, "Pa", atLeast(0),
           "C2, the thermally activated hardening of eps_p^(1/2) (fcc metals).");
  k.number("C3", p.C3, 0.0, "1/K", atLeast(0), "C3, the thermal softening coefficient.");
  // The metals of Zerilli & Armstrong have C4 ~ 1e-4/K; past 1e-2/K exp(C4 T ln rate) overflows
  // in reach of a hypervelocity scene (T 3000 K, rate 1e10/s) and the return stalls.
  k.number("C4", p.C4, 0.0, "1/K", within(0, 1e-2),
           "C4, the rate sensitivity of the thermal activation.");
  k.number("C5", p.C5, 0.0, "Pa", strength(atLeast(0)),
           "C5, the athermal strain hardening (bcc metals).");
  k.rule("C0", "C0 + C1 + C2 + C5 > 0", "else the model has no stress to yield at",
         p.C0 + p.C1 + p.C2 + p.C5 > 0.0, p.C0);
  k.number("n", p.n, 1.0, "", above(0), "n, the exponent of C5's hardening.");
  k.number("reference_strain_rate", p.rate0, 1.0, "1/s", above(0),
           "rate0 of the rate term C4 T ln(rate/rate0).");
  k.number("room_temperature", p.Troom, required, "K", temperature(above(0)),
           "The starting temperature (absolute).");
  heating(k, p.cp, p.chi);
}

template <class K> void keysOf(K& k, materials::CapPlasticity& p) {
  k.section("cap",
            "Porous rock with pore fluid, two surfaces, after Arenisca (Austin 2013, ch. 4); "
            "no eos.");
  k.number("bulk_modulus", p.K, required, "Pa", modulus(above(0)),
           "K, the bulk modulus (its own EOS).");
  shearModulus(k, p.G);
  k.number("peak_i1", p.peakI1, required, "Pa", atLeast(0),
           "I1 at the tensile vertex of the surface.");
  k.number("f_slope", p.fSlope, required, "", above(0),
           "The Drucker-Prager slope: Ff = f_slope (peak_i1 - I1).");
  k.number("cap_ratio", p.capRatio, required, "", above(0),
           "The elliptical cap's axis ratio: kappa - X = cap_ratio Ff(kappa).");
  k.number("crush_p0", p.P0, required, "Pa", below(0),
           "P0, the cap's initial position in I1 (compression negative).");
  k.number("crush_p1", p.P1, required, "1/Pa", above(0),
           "P1 of the crush curve eps_v^p = P3 (exp(P1 (X - P0)) - 1) (Austin 2013, Eq. 4.5).");
  k.number("crush_p3", p.P3, required, "", above(0),
           "P3, the largest plastic compaction strain of the crush curve.");
  k.flag("hardening", p.hardening, true,
         "The cap moves with the plastic volume change; false: it stays at crush_p0.");
  k.number("dilatancy", p.dilatancy, 1.0, "", within(0, 1),
           "beta, the share of the associated dilation on the shear side (1: associated).");
  k.number("fluid_bulk_modulus", p.Kf, 0.0, "Pa", atLeast(0),
           "K_f of the pore fluid, undrained; 0: drained at initial_pore_pressure.");
  k.number("initial_pore_pressure", p.pf0, 0.0, "Pa", atLeast(0),
           "p_f0, the pore pressure at the start (Terzaghi's effective stress).");
  k.number("rate_t1", p.T1, 0.0, "s^(1-T2)", atLeast(0),
           "T1 of the overstress's relaxation time tau = T1 (1/|D|)^T2 (Arenisca's Duvaut-Lions "
           "rate dependence); 0: rate-independent.");
  k.number("rate_t2", p.T2, 0.0, "", atLeast(0),
           "T2, the relaxation time's exponent of the strain rate; 0: tau = T1 at any rate.");
}

const auto kKeys = [](auto& k, auto& p) -> decltype(keysOf(k, p)) { keysOf(k, p); };

} // namespace

std::vector<KeySection> strength() {
  return describeTypes<StrengthModel>(
      kPath, "The deviatoric stress: elasticity, plasticity and hardening; without it, a fluid.",
      "The strength model; the other keys are its type's.", kKeys);
}

StrengthModel readStrength(const deck_detail::TableReader& r, std::string_view type) {
  return readType<StrengthModel>(r, kPath, type, kKeys);
}

} // namespace spall::io::keys

std::string_view spall::strengthTypeName(const StrengthConfig& c) {
  return io::keys::typeName(c.model, io::keys::kPath, io::keys::kKeys);
}
