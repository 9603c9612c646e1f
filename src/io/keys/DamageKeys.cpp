// A material's damage model, material.damage, by type: the reference's rows and the reader's
// reads (Keys.hpp), one function per model of materials/Damage.hpp.
#include "Keys.hpp"

namespace spall::io::keys {

namespace {

constexpr std::string_view kPath = "material.damage";

// mode: one damage per particle (Benz & Asphaug 1995) or one per direction (Owen 2010).
constexpr NameTable<bool, 2> kModes{{{{false, "scalar"}, {true, "tensor"}}}};

template <class K> void keysOf(K& k, materials::GradyKipp& p) {
  k.section("grady_kipp",
            "Tensile flaws of a Weibull law that grow cracks (Grady & Kipp; Benz & Asphaug 1994, "
            "1995).");
  k.number("weibull_k", p.k, required, "1/m^3", above(0),
           "k of the Weibull law n(eps) = k eps^m: flaws per unit volume at unit strain.");
  k.number("weibull_m", p.m, required, "", above(0), "m, the Weibull exponent.");
  k.number("crack_speed", p.crackSpeed, 0.4, "", withinOpenClosed(0, 1),
           "The crack growth speed over the longitudinal sound speed.");
  k.choice("mode", p.tensor, kModes, false,
           "scalar: one damage per particle; tensor: one per principal direction (Owen 2010).");
}

template <class K> void keysOf(K& k, materials::JohnsonCookDamage& p) {
  k.section("johnson_cook", "Johnson & Cook (1985), Austin (2013) Eq. 6.5: dD = d eps_p / eps_f; "
                            "needs plastic strain.");
  k.number("D1", p.D1, required, "", any(),
           "D1 of eps_f = [D1 + D2 exp(D3 sigma*)][1 + D4 ln rate*][1 + D5 T*].");
  k.number("D2", p.D2, required, "", any(), "D2, the triaxiality term's coefficient.");
  k.number("D3", p.D3, required, "", any(),
           "D3, the triaxiality exponent (sigma* = -p / sigma_eq).");
  k.number("D4", p.D4, required, "", any(), "D4, the strain rate coefficient.");
  k.number("D5", p.D5, required, "", any(), "D5, the temperature coefficient.");
  k.number("reference_strain_rate", p.rate0, required, "1/s", above(0),
           "The plastic strain rate below which the rate term is 1.");
  k.number("room_temperature", p.Troom, required, "K", temperature(above(0)),
           "T* = 0 of the temperature term.");
  k.number("melt_temperature", p.Tmelt, required, "K",
           temperature(above("room_temperature", p.Troom)), "T* = 1 of the temperature term.");
}

const auto kKeys = [](auto& k, auto& p) -> decltype(keysOf(k, p)) { keysOf(k, p); };

} // namespace

std::vector<KeySection> damage() {
  return describeTypes<DamageModel>(
      kPath, "Damage D in [0, 1] that degrades the stress; needs a strength model, not cap.",
      "The damage model; the other keys are its type's.", kKeys);
}

DamageModel readDamage(const deck_detail::TableReader& r, std::string_view type) {
  return readType<DamageModel>(r, kPath, type, kKeys);
}

} // namespace spall::io::keys

std::string_view spall::damageTypeName(const DamageConfig& c) {
  return io::keys::typeName(c.model, io::keys::kPath, io::keys::kKeys);
}
