#pragma once
// A section's or a model's keys written once: the same function lists them for the reference
// (`spall keys`, decks/keys.md, the reader's allow-list) and reads them from a deck, with the
// default and the bound it prints. A key function takes a visitor K and the parameters (a model,
// or a section's configuration, whose initializers are the defaults `keep` prints):
//
//   template <class K> void keysOf(K& k, materials::VonMises& p) {
//     k.section("von_mises", "Perfect plasticity ...");
//     k.number("yield_stress", p.Y, required, "Pa", above(0), "Y, the von Mises yield stress.");
//   }
//
// Describe collects the rows; Read fills p from the deck's table and refuses a value outside its
// bound with the bound's text. What a row cannot check itself (a vector not zero, a name of
// another entry) the section's reader checks after, and the row says it in prose. A typed table
// whose types are the alternatives of a variant is described and read by describeTypes / readType
// below.
#include "../DeckDetail.hpp"
#include "spall/io/DeckKeys.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace spall::io::keys {

// Where a value is probably a slip (a unit typed wrong), not an error: outside [lo, hi] the reader
// warns, saying what a value below lo (`low`) or above hi (`high`) suggests. 0 is exempt (a term
// switched off).
struct Plausible {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  std::string_view low{}, high{};
  bool set() const { return !low.empty() || !high.empty(); }
};

// What a number must be: "> 0", "[0, 1]", "> room_temperature" (another key of the same table,
// read before this one).
struct Bound {
  enum class Kind { Any, Above, AtLeast, Below, AtMost, Closed, OpenClosed, ClosedOpen, Open };
  Kind kind = Kind::Any;
  double lo = 0.0, hi = 0.0;
  std::string_view loKey{};        // lo is this key's value...
  const double* loValue = nullptr; // ...read from here when checked
  std::string_view hiKey{};        // the same for hi
  const double* hiValue = nullptr;
  bool infinite = false; // inf is a value (h_max = inf: no bound)
  Plausible plausible{};
  bool holds(double v) const;
  Bound orInfinite() const {
    Bound b = *this;
    b.infinite = true;
    return b;
  }
  // The same bound, warning outside [lo, hi] (Plausible).
  Bound warnOutside(double lo, double hi, std::string_view low, std::string_view high) const {
    Bound b = *this;
    b.plausible = {lo, hi, low, high};
    return b;
  }
  // The bound, then where it warns and why: "> 0; warns below 1e+05 (MPa typed for Pa?) or
  // above 1e+13".
  std::string text() const;
  std::string strictText() const; // the bound alone: what an error message says
};
inline Bound any() {
  return {};
}
inline Bound above(double lo) {
  return {Bound::Kind::Above, lo};
}
inline Bound atLeast(double lo) {
  return {Bound::Kind::AtLeast, lo};
}
inline Bound below(double hi) {
  return {Bound::Kind::Below, 0.0, hi};
}
inline Bound atMost(double hi) {
  return {Bound::Kind::AtMost, 0.0, hi};
}
inline Bound within(double lo, double hi) {
  return {Bound::Kind::Closed, lo, hi};
} // [lo, hi]
inline Bound withinOpenClosed(double lo, double hi) {
  return {Bound::Kind::OpenClosed, lo, hi};
}
inline Bound withinClosedOpen(double lo, double hi) {
  return {Bound::Kind::ClosedOpen, lo, hi};
} // [lo, hi)
inline Bound withinOpenClosed(double lo, std::string_view hiKey, const double& hi) {
  return {Bound::Kind::OpenClosed, lo, 0.0, {}, nullptr, hiKey, &hi};
}
inline Bound above(std::string_view key, const double& value) {
  return {Bound::Kind::Above, 0.0, 0.0, key, &value};
}
inline Bound atLeast(std::string_view key, const double& value) {
  return {Bound::Kind::AtLeast, 0.0, 0.0, key, &value};
}
inline Bound withinClosedOpen(double lo, std::string_view hiKey, const double& hi) {
  return {Bound::Kind::ClosedOpen, lo, 0.0, {}, nullptr, hiKey, &hi};
}
// (lo, hi), each end another key's value or (lo) a number.
inline Bound between(std::string_view loKey, const double& lo, std::string_view hiKey,
                     const double& hi) {
  return {Bound::Kind::Open, 0.0, 0.0, loKey, &lo, hiKey, &hi};
}
inline Bound within(double lo, std::string_view hiKey, const double& hi) {
  return {Bound::Kind::Closed, lo, 0.0, {}, nullptr, hiKey, &hi};
}
inline Bound between(double lo, std::string_view hiKey, const double& hi) {
  return {Bound::Kind::Open, lo, 0.0, {}, nullptr, hiKey, &hi};
}

// The slips plausibility catches (Plausible), each range wide enough for every material a
// hydrocode meets: moduli from rubber's shear modulus (~1e6 Pa) to diamond's bulk modulus
// (4.4e11 Pa); strengths from soft clay (~1e4 Pa) to ceramics and diamond (~1e10 Pa); room and
// melt temperatures from liquid nitrogen (77 K) to tungsten's melt (3695 K); sound speeds from
// foams and soils (~100 m/s) to beryllium and diamond (12-18 km/s); specific heats from lead's
// 129 J/(kg K) to water's 4186. A value typed in the wrong unit is 1e3 to 1e9 away from them.
inline Bound modulus(Bound b) {
  return b.warnOutside(1e5, 1e13, "MPa or GPa typed for Pa?", "stiffer than diamond");
}
inline Bound strength(Bound b) {
  return b.warnOutside(1e4, 1e11, "MPa typed for Pa?", "stronger than diamond");
}
inline Bound temperature(Bound b) {
  return b.warnOutside(50.0, 6000.0, "Celsius typed for kelvin?", "hotter than any solid melts");
}
inline Bound soundSpeed(Bound b) {
  return b.warnOutside(100.0, 2e4, "km/s typed for m/s?", "faster than any material's");
}
inline Bound specificHeat(Bound b) {
  return b.warnOutside(50.0, 1e4, "kJ/(kg K) typed for J/(kg K)?", "above any solid's");
}

// A bound by another key's value reads it when checked: never from a temporary.
Bound withinOpenClosed(double, std::string_view, const double&&) = delete;
Bound above(std::string_view, const double&&) = delete;
Bound atLeast(std::string_view, const double&&) = delete;
Bound withinClosedOpen(double, std::string_view, const double&&) = delete;
Bound between(std::string_view, const double&&, std::string_view, const double&) = delete;
Bound between(std::string_view, const double&, std::string_view, const double&&) = delete;
Bound within(double, std::string_view, const double&&) = delete;
Bound between(double, std::string_view, const double&&) = delete;

// The default of a key: `required` (the deck must give it), `off` (absent leaves the
// parameter's own value, meaning the feature is off: "none" in the reference), or a value.
struct Required {};
inline constexpr Required required{};
struct Off {};
inline constexpr Off off{};
// `keep`: the parameter's own initial value (a configuration's initializer) is the default.
struct Keep {};
inline constexpr Keep keep{};
// A default that other parts of the deck decide, printed as `text`: absent leaves the parameter
// as it is, for the reader to settle once the deck is read.
struct Depends {
  std::string_view text;
};

// A number as a TOML deck writes it ("1.0", "0.4", "1e-05").
std::string tomlNumber(double v);

// Collects a section's rows.
class Describe {
public:
  explicit Describe(std::string_view path) { section_.path = path; }

  void section(std::string_view type, std::string_view meaning) {
    section_.type = type;
    section_.meaning = meaning;
  }
  void number(std::string_view key, double&, Required, std::string_view unit, Bound b,
              std::string_view meaning) {
    row(key, "float", "required", unit, b.text(), meaning);
  }
  void number(std::string_view key, double&, double fallback, std::string_view unit, Bound b,
              std::string_view meaning) {
    row(key, "float", tomlNumber(fallback), unit, b.text(), meaning);
  }
  void number(std::string_view key, double&, Off, std::string_view unit, Bound b,
              std::string_view meaning) {
    row(key, "float", "none", unit, b.text(), meaning);
  }
  void number(std::string_view key, std::optional<double>&, Off, std::string_view unit, Bound b,
              std::string_view meaning) {
    row(key, "float", "none", unit, b.text(), meaning);
  }
  void number(std::string_view key, double& v, Keep, std::string_view unit, Bound b,
              std::string_view meaning) {
    row(key, "float", tomlNumber(v), unit, b.text(), meaning);
  }
  void number(std::string_view key, double&, Depends d, std::string_view unit, Bound b,
              std::string_view meaning) {
    row(key, "float", std::string(d.text), unit, b.text(), meaning);
  }
  template <class I>
  void integer(std::string_view key, I&, Required, std::string_view unit, Bound b,
               std::string_view meaning) {
    row(key, "integer", "required", unit, b.text(), meaning);
  }
  template <class I>
  void integer(std::string_view key, I& v, Keep, std::string_view unit, Bound b,
               std::string_view meaning) {
    row(key, "integer", std::to_string(v), unit, b.text(), meaning);
  }
  template <class I>
  void integer(std::string_view key, I&, Depends d, std::string_view unit, Bound b,
               std::string_view meaning) {
    row(key, "integer", std::string(d.text), unit, b.text(), meaning);
  }
  void flag(std::string_view key, bool&, bool fallback, std::string_view meaning) {
    row(key, "boolean", fallback ? "true" : "false", "", "", meaning);
  }
  void flag(std::string_view key, bool& v, Keep, std::string_view meaning) {
    row(key, "boolean", v ? "true" : "false", "", "", meaning);
  }
  void text(std::string_view key, std::string&, Required, std::string_view meaning) {
    row(key, "string", "required", "", "", meaning);
  }
  void text(std::string_view key, std::string& v, Keep, std::string_view meaning) {
    row(key, "string", quoted(v), "", "", meaning);
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E&, const NameTable<E, N>& names, E fallback,
              std::string_view meaning) {
    row(key, oneOf(names.names()), quoted(names(fallback)), "", "", meaning);
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E& v, const NameTable<E, N>& names, Keep,
              std::string_view meaning) {
    row(key, oneOf(names.names()), quoted(names(v)), "", "", meaning);
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E&, const NameTable<E, N>& names, Depends d,
              std::string_view meaning) {
    row(key, oneOf(names.names()), std::string(d.text), "", "", meaning);
  }
  void number(std::string_view key, std::optional<double>&, Depends d, std::string_view unit,
              Bound b, std::string_view meaning) {
    row(key, "float", std::string(d.text), unit, b.text(), meaning);
  }
  // Lists and vectors: `bounds` is prose, which the section's reader checks after.
  // `type`: "float[3]" for a key of a 3D-only table.
  template <class D>
  void vector(std::string_view key, std::vector<double>&, D d, std::string_view unit,
              std::string_view bounds, std::string_view meaning,
              std::string_view type = "float[dim]") {
    row(key, std::string(type), fallbackText(d), unit, std::string(bounds), meaning);
  }
  void matrix(std::string_view key, std::optional<std::vector<std::vector<double>>>&, Off,
              std::string_view unit, std::string_view bounds, std::string_view meaning) {
    row(key, "float[dim][dim]", "none", unit, std::string(bounds), meaning);
  }
  void matrix(std::string_view key, std::vector<std::vector<double>>&, Required,
              std::string_view unit, std::string_view bounds, std::string_view meaning) {
    row(key, "float[dim][dim]", "required", unit, std::string(bounds), meaning);
  }
  template <class D>
  void strings(std::string_view key, std::vector<std::string>&, D d, std::string_view bounds,
               std::string_view meaning) {
    row(key, "strings", fallbackText(d), "", std::string(bounds), meaning);
  }
  void integers(std::string_view key, std::vector<std::int64_t>&, Depends d,
                std::string_view bounds, std::string_view meaning) {
    row(key, "integers", std::string(d.text), "", std::string(bounds), meaning);
  }
  void text(std::string_view key, std::string&, Required, std::string_view bounds,
            std::string_view meaning) {
    row(key, "string", "required", "", std::string(bounds), meaning);
  }
  // A condition the row states and the reader enforces with `message` (after the key's quoted
  // path): "'grid' writes MPM's grid: it needs ...".
  void require(std::string_view key, std::string_view text, bool, const std::string&) {
    if (!text.empty()) rule(key, text, "", true, 0.0);
  }
  // A condition on `key` that another key's `require` enforces: its text in key's row.
  void note(std::string_view key, std::string_view text) { rule(key, text, "", true, 0.0); }
  // A sub-table (`many`: an array of tables), read by its own key function.
  void table(std::string_view key, std::string_view fallback, std::string_view bounds,
             std::string_view meaning, bool many = false) {
    row(key, many ? "[[table]]" : "table", std::string(fallback), "", std::string(bounds), meaning);
  }
  // A key the section's reader takes itself (vectors, lists, names of other entries): its row.
  void other(std::string_view key, std::string_view type, std::string_view fallback,
             std::string_view unit, std::string_view bounds, std::string_view meaning) {
    row(key, std::string(type), std::string(fallback), unit, std::string(bounds), meaning);
  }
  // A condition over several keys, checked after them; its text joins `key`'s bound, `why` is
  // for the reader's message.
  void rule(std::string_view key, std::string_view text, std::string_view why, bool, double);

  KeySection take() { return std::move(section_); }
  static std::string fallbackText(Required) { return "required"; }
  static std::string fallbackText(Depends d) { return std::string(d.text); }
  static std::string oneOf(const std::vector<std::string_view>& names);
  static std::string quoted(std::string_view name); // as a deck writes a string: "\"plastic\""

private:
  void row(std::string_view key, std::string type, std::string fallback, std::string_view unit,
           std::string bounds, std::string_view meaning) {
    section_.keys.push_back(
        {key, std::move(type), std::move(fallback), unit, std::move(bounds), meaning});
  }
  KeySection section_;
};

// Reads a section from a deck table whose keys the allow-list has already checked.
class Read {
public:
  // `dimension`: the length of a vector key's value (run.dimension).
  explicit Read(const deck_detail::TableReader& r, std::size_t dimension = 0)
      : r_(r), dimension_(dimension) {}

  void section(std::string_view, std::string_view) {}
  void number(std::string_view key, double& v, Required, std::string_view unit, Bound b,
              std::string_view) {
    v = r_.required(r_.number(key, b.infinite), key);
    check(key, v, unit, b);
  }
  void number(std::string_view key, double& v, double fallback, std::string_view unit, Bound b,
              std::string_view) {
    const auto given = r_.number(key, b.infinite);
    v = given.value_or(fallback);
    if (!given) r_.noteDefault(key, tomlNumber(v));
    check(key, v, unit, b);
  }
  void number(std::string_view key, double& v, Off, std::string_view unit, Bound b,
              std::string_view) {
    if (const auto given = r_.number(key, b.infinite)) {
      v = *given;
      check(key, v, unit, b);
    }
  }
  void number(std::string_view key, std::optional<double>& v, Off, std::string_view unit, Bound b,
              std::string_view) {
    if (const auto given = r_.number(key, b.infinite)) {
      check(key, *given, unit, b);
      v = given;
    }
  }
  void number(std::string_view key, double& v, Keep, std::string_view unit, Bound b,
              std::string_view) {
    const auto given = r_.number(key, b.infinite);
    v = given.value_or(v);
    if (!given) r_.noteDefault(key, tomlNumber(v));
    check(key, v, unit, b);
  }
  void number(std::string_view key, double& v, Depends, std::string_view unit, Bound b,
              std::string_view meaning) {
    number(key, v, off, unit, b, meaning); // absent: as it is, as with `off`
  }
  template <class I>
  void integer(std::string_view key, I& v, Required, std::string_view unit, Bound b,
               std::string_view) {
    v = toInteger<I>(key, r_.required(r_.integer(key), key), unit, b);
  }
  template <class I>
  void integer(std::string_view key, I& v, Keep, std::string_view unit, Bound b, std::string_view) {
    if (const auto given = r_.integer(key))
      v = toInteger<I>(key, *given, unit, b);
    else
      r_.noteDefault(key, std::to_string(v));
  }
  template <class I>
  void integer(std::string_view key, I& v, Depends, std::string_view unit, Bound b,
               std::string_view) {
    if (const auto given = r_.integer(key)) v = toInteger<I>(key, *given, unit, b);
  }
  void flag(std::string_view key, bool& v, bool fallback, std::string_view) {
    const auto given = r_.boolean(key);
    v = given.value_or(fallback);
    if (!given) r_.noteDefault(key, v ? "true" : "false");
  }
  void flag(std::string_view key, bool& v, Keep, std::string_view) {
    const auto given = r_.boolean(key);
    v = given.value_or(v);
    if (!given) r_.noteDefault(key, v ? "true" : "false");
  }
  void text(std::string_view key, std::string& v, Required, std::string_view) {
    v = r_.required(r_.string(key), key);
  }
  void text(std::string_view key, std::string& v, Keep, std::string_view) {
    const auto given = r_.string(key);
    v = given.value_or(v);
    if (!given) r_.noteDefault(key, Describe::quoted(v));
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E& v, const NameTable<E, N>& names, E fallback,
              std::string_view) {
    v = r_.choice(key, names, fallback);
    if (!r_.has(key)) r_.noteDefault(key, Describe::quoted(names(v)));
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E& v, const NameTable<E, N>& names, Keep, std::string_view) {
    v = r_.choice(key, names, v);
    if (!r_.has(key)) r_.noteDefault(key, Describe::quoted(names(v)));
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E& v, const NameTable<E, N>& names, Depends, std::string_view) {
    if (r_.has(key)) v = r_.choice(key, names, v);
  }
  void number(std::string_view key, std::optional<double>& v, Depends, std::string_view unit,
              Bound b, std::string_view meaning) {
    number(key, v, off, unit, b, meaning);
  }
  void vector(std::string_view key, std::vector<double>& v, Required, std::string_view,
              std::string_view, std::string_view, std::string_view = {}) {
    v = r_.required(r_.vector(key, dimension_), key);
  }
  void vector(std::string_view key, std::vector<double>& v, Depends, std::string_view,
              std::string_view, std::string_view, std::string_view = {}) {
    if (auto given = r_.vector(key, dimension_)) v = std::move(*given);
  }
  void matrix(std::string_view key, std::optional<std::vector<std::vector<double>>>& v, Off,
              std::string_view, std::string_view, std::string_view) {
    if (auto given = r_.matrix(key, dimension_)) v = std::move(given);
  }
  void matrix(std::string_view key, std::vector<std::vector<double>>& v, Required, std::string_view,
              std::string_view, std::string_view) {
    v = r_.required(r_.matrix(key, dimension_), key);
  }
  void strings(std::string_view key, std::vector<std::string>& v, Required, std::string_view,
               std::string_view) {
    v = r_.required(r_.strings(key), key);
  }
  void strings(std::string_view key, std::vector<std::string>& v, Depends, std::string_view,
               std::string_view) {
    if (auto given = r_.strings(key)) v = std::move(*given);
  }
  void integers(std::string_view key, std::vector<std::int64_t>& v, Depends, std::string_view,
                std::string_view) {
    if (auto given = r_.integers(key)) v = std::move(*given);
  }
  void text(std::string_view key, std::string& v, Required, std::string_view, std::string_view) {
    v = r_.required(r_.string(key), key);
  }
  void require(std::string_view key, std::string_view, bool ok, const std::string& message) const {
    if (!ok) r_.fail(key, r_.quoted(key) + " " + message);
  }
  void note(std::string_view, std::string_view) {}
  void table(std::string_view, std::string_view, std::string_view, std::string_view, bool = false) {
  }
  void other(std::string_view, std::string_view, std::string_view, std::string_view,
             std::string_view, std::string_view) {}
  void rule(std::string_view key, std::string_view text, std::string_view why, bool ok,
            double got) const;

private:
  void check(std::string_view key, double v, std::string_view unit, const Bound& b) const;
  void plausible(std::string_view key, double v, std::string_view unit, const Bound& b) const;
  // An integer in its bound and in I's range.
  template <class I>
  I toInteger(std::string_view key, std::int64_t v, std::string_view unit, const Bound& b) const {
    check(key, static_cast<double>(v), unit, b);
    r_.check(std::in_range<I>(v), key,
             fmt::format("an integer in [{}, {}]", std::numeric_limits<I>::min(),
                         std::numeric_limits<I>::max()),
             static_cast<double>(v));
    return static_cast<I>(v);
  }
  const deck_detail::TableReader& r_;
  std::size_t dimension_;
};

// Calls f(std::type_identity<T>{}) for each alternative T of Variant, in order.
template <class Variant, class F> void forEachAlternative(F&& f) {
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(std::type_identity<std::variant_alternative_t<I, Variant>>{}), ...);
  }
  (std::make_index_sequence<std::variant_size_v<Variant>>{});
}

// The section of one type T (its name, meaning and rows).
template <class T, class Keys> KeySection sectionOf(std::string_view path, Keys keys) {
  T p{};
  Describe d(path);
  keys(d, p);
  return d.take();
}

// The sections of a typed table at `path` whose types are Variant's alternatives that have keys
// (`keys(k, p)` calls the alternative's key function): first the table's own section, holding
// `type`, then one per type.
template <class Variant, class Keys>
std::vector<KeySection> describeTypes(std::string_view path, std::string_view meaning,
                                      std::string_view typeMeaning, Keys keys) {
  std::vector<KeySection> out{{path, "", meaning, {}}};
  std::vector<std::string_view> names;
  forEachAlternative<Variant>([&](auto t) {
    using T = typename decltype(t)::type;
    if constexpr (std::is_invocable_v<Keys, Describe&, T&>) {
      out.push_back(sectionOf<T>(path, keys));
      names.push_back(out.back().type);
    }
  });
  out.front().keys.push_back({"type", Describe::oneOf(names), "required", "", "", typeMeaning});
  return out;
}

// The name of the type a model has in its table.
template <class Variant, class Keys>
std::string_view typeName(const Variant& model, std::string_view path, Keys keys) {
  return std::visit(
      [&](const auto& m) -> std::string_view {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_invocable_v<Keys, Describe&, T&>) {
          return sectionOf<T>(path, keys).type;
        } else {
          return "none";
        }
      },
      model);
}

// The model of the type named `type` (already checked against the table's types), its
// parameters read from r.
template <class Variant, class Keys>
Variant readType(const deck_detail::TableReader& r, std::string_view path, std::string_view type,
                 Keys keys) {
  std::optional<Variant> model;
  forEachAlternative<Variant>([&](auto t) {
    using T = typename decltype(t)::type;
    if constexpr (std::is_invocable_v<Keys, Describe&, T&>) {
      if (model || sectionOf<T>(path, keys).type != type) return;
      T p{};
      Read read(r);
      keys(read, p);
      model = p;
    }
  });
  if (!model)
    throw std::logic_error("internal: " + std::string(path) + " type '" + std::string(type) +
                           "' has no model");
  return *model;
}

// The sections read from their tables (src/io/keys/*Keys.cpp).
void readSolver(const deck_detail::TableReader& r, SolverConfig& s);
void readRun(const deck_detail::TableReader& r, RunConfig& run);
void readDecomposition(const deck_detail::TableReader& r, DecompositionConfig& d);
// `endTime`, `method`: run.end_time and solver.method, which bound output.every and grid.
void readOutput(const deck_detail::TableReader& r, OutputConfig& o, double endTime,
                SolverMethod method);
void readCheckpoint(const deck_detail::TableReader& r, CheckpointConfig& c);
// `nodesPerH`: solver.nodes_per_h, which bounds link_length.
void readFragments(const deck_detail::TableReader& r, FragmentsConfig& c, double nodesPerH);
void readDamping(const deck_detail::TableReader& r, DampingConfig& d);
void readEnergySource(const deck_detail::TableReader& r, EnergySourceConfig& e,
                      std::size_t dimension);
// A [[boundary]] by its type; the deck reader checks the body and the rz geometry.
void readBoundary(const deck_detail::TableReader& r, BoundaryConfig& b, std::size_t dimension,
                  bool rz);
// A [[body]]'s own keys (not its name, shape or velocity fields); the deck reader checks the
// material they name.
void readBody(const deck_detail::TableReader& r, BodyConfig& b, std::size_t dimension);
// A body's shape, by its type; `rz`: run.geometry = "rz" (x the radius).
void readShape(const deck_detail::TableReader& r, ShapeConfig& s, std::size_t dimension, bool rz);
// A body's velocity fields (added to its uniform velocity where the particles are made).
void readVelocityFields(const deck_detail::TableReader& r, std::size_t dimension, BodyConfig& b);
// A body's grading table, if given: one reference, unit directions, max_spacing >= spacing.
void readGrading(const deck_detail::TableReader& r, std::size_t dimension, BodyConfig& b);
// A [[jet]]'s keys but its name and segments (the deck reader makes the segments' bodies).
struct JetConfig {
  std::string material;
  std::vector<double> axis, entry;
  double spacing = 0.0;
};
JetConfig readJet(const deck_detail::TableReader& r, std::size_t dimension);
// Without the probe's name (the deck reader's, with the names of all entries).
void readProbe(const deck_detail::TableReader& r, ProbeConfig& p, std::size_t dimension);
// The keys of [penetration] as given; the reader checks the bodies they name.
void readPenetration(const deck_detail::TableReader& r, PenetrationConfig& c,
                     std::size_t dimension);

// A [[material]]'s own keys (density, erosion); its models' tables are read by those below.
void readMaterialKeys(const deck_detail::TableReader& r, MaterialConfig& m);

// The material's models read from their tables (src/io/keys/*Keys.cpp), `type` already
// checked against the table's types.
materials::Eos readEos(const deck_detail::TableReader& r, std::string_view type,
                       double& minPressure);
StrengthModel readStrength(const deck_detail::TableReader& r, std::string_view type);
DamageModel readDamage(const deck_detail::TableReader& r, std::string_view type);
void readPorosity(const deck_detail::TableReader& r, PorosityConfig& c);

} // namespace spall::io::keys
