// A material's porosity model, material.porosity, by type: the reference's rows and the reader's
// reads (Keys.hpp) for the P-alpha model of materials/Porosity.hpp.
#include "Keys.hpp"

#include <algorithm>

namespace spall::io::keys {

namespace {

constexpr std::string_view kPath = "material.porosity";

template <class K> void keysOf(K& k, PorosityConfig& c) {
  k.section("p_alpha", "P-alpha: the distension on an irreversible crush curve (Herrmann 1969; "
                       "Jutzi et al. 2008).");
  k.number("alpha0", c.alpha0, required, "", atLeast(1),
           "Initial distension, solid over bulk density: the body starts at density / alpha0.");
  k.number("elastic_pressure", c.elastic_pressure, required, "Pa", atLeast(0),
           "Pe: below it the pores do not crush.");
  k.number("solid_pressure", c.solid_pressure, required, "Pa",
           above("elastic_pressure", c.elastic_pressure),
           "Ps: at it the material is fully compacted (alpha = 1).");
  k.number("exponent", c.exponent, 2.0, "", above(0),
           "n of the crush curve 1 + (alpha0 - 1) ((Ps - P)/(Ps - Pe))^n (of its last stage).");
  k.number("transition_pressure", c.transition_pressure, off, "Pa",
           between("elastic_pressure", c.elastic_pressure, "solid_pressure", c.solid_pressure),
           "Pt of a two-stage curve; with alpha_transition and exponent_transition, all or none.");
  k.number("alpha_transition", c.alpha_transition, off, "", between(1, "alpha0", c.alpha0),
           "alpha_t, the distension at transition_pressure (two stages).");
  k.number("exponent_transition", c.exponent_transition, off, "", above(0),
           "n_t, the exponent of the first stage, alpha0 to alpha_t (two stages).");
  // 0 (absent): the matrix's; checked against the matrix's sound speed where the EOS is built
  // (app/Setup.cpp).
  k.number("elastic_sound_speed", c.elastic_sound_speed, off, "m/s", above(0),
           "c_e, the porous material's elastic wave speed at alpha0 (Jutzi et al. 2008).");
  k.rule("elastic_sound_speed", "alpha0 > 1",
         "it is the speed of the porous material at alpha0, and alpha0 = 1 is not porous",
         c.elastic_sound_speed == 0.0 || c.alpha0 > 1.0, c.elastic_sound_speed);
}

} // namespace

std::vector<KeySection> porosity() {
  Describe d(kPath);
  PorosityConfig c;
  keysOf(d, c);
  std::vector<KeySection> out{{kPath,
                               "",
                               "Sub-resolution porosity around the material's eos; not with a cap "
                               "strength.",
                               {{"type", Describe::oneOf({"p_alpha"}), "required", "", "",
                                 "The porosity model; the other keys are its type's."}}}};
  out.push_back(d.take());
  return out;
}

void readPorosity(const deck_detail::TableReader& r, PorosityConfig& c) {
  Read read(r);
  keysOf(read, c);
  const int given = int(c.transition_pressure.has_value()) + int(c.alpha_transition.has_value()) +
                    int(c.exponent_transition.has_value());
  if (given > 0 && given < 3) { // point at a key that is there, name the one that is not
    const deck_detail::Names keys{"transition_pressure", "alpha_transition", "exponent_transition"};
    const auto there = *std::find_if(keys.begin(), keys.end(), [&](auto k) { return r.has(k); });
    const auto absent = *std::find_if(keys.begin(), keys.end(), [&](auto k) { return !r.has(k); });
    r.fail(there, "a two-stage crush curve in " + r.context().human +
                      " needs transition_pressure, alpha_transition and exponent_transition; '" +
                      std::string(absent) + "' is missing");
  }
  if (r.has("elastic_sound_speed")) c.soundSpeedWhere = r.whereValue("elastic_sound_speed");
}

} // namespace spall::io::keys
