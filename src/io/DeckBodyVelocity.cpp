// A body's velocity fields (added to its uniform `velocity` where the particles are made):
// radial_velocity, cantilever_velocity, linear_velocity, sine_velocity.
#include "DeckDetail.hpp"

#include <optional>

namespace spall::io::deck_detail {

void readVelocityFields(const TableReader& r, std::size_t dimension, BodyConfig& b) {
  // Key `key`'s inline table, read against its schema ("body.KEY"); none when absent.
  const auto table = [&r](const char* key) -> std::optional<TableReader> {
    const toml::table* t = r.subtable(key);
    if (!t) return std::nullopt;
    TableReader sub(*t, r.context().child(key), r.deckPath());
    sub.allowOnly(*schemaKeys(std::string("body.") + key));
    return sub;
  };
  const auto point = [dimension](const TableReader& t, const char* key) {
    return t.required(t.vector(key, dimension), key);
  };
  if (const auto rv = table("radial_velocity"))
    b.radial_velocity =
        RadialVelocityConfig{point(*rv, "center"), rv->required(rv->number("speed"), "speed")};
  if (const auto cv = table("cantilever_velocity")) {
    if (dimension < 2)
      r.fail("cantilever_velocity", r.quoted("cantilever_velocity") +
                                        " needs run.dimension 2 or 3 (a transverse velocity)");
    CantileverVelocityConfig c;
    c.root = point(*cv, "root");
    c.length = cv->required(cv->number("length"), "length");
    cv->check(c.length > 0.0, "length", "> 0", c.length);
    c.tip_speed = cv->required(cv->number("tip_speed"), "tip_speed");
    b.cantilever_velocity = c;
  }
  if (const auto lv = table("linear_velocity"))
    b.linear_velocity = LinearVelocityConfig{
        point(*lv, "center"), lv->required(lv->matrix("gradient", dimension), "gradient")};
  if (const auto sv = table("sine_velocity"))
    b.sine_velocity =
        SineVelocityConfig{point(*sv, "amplitude"), point(*sv, "wavevector"), point(*sv, "origin")};
}

} // namespace spall::io::deck_detail
