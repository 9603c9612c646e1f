#pragma once
// A model's keys written once: the same function lists them for the reference (`spall keys`,
// decks/keys.md, the reader's allow-list) and reads them from a deck, with the default and the
// bound it prints. A model's key function takes a visitor K and the model's parameters:
//
//   template <class K> void keysOf(K& k, materials::VonMises& p) {
//     k.section("von_mises", "Perfect plasticity ...");
//     k.number("yield_stress", p.Y, required, "Pa", above(0), "Y, the von Mises yield stress.");
//   }
//
// Describe collects the rows; Read fills p from the deck's table and refuses a value outside its
// bound with the bound's text. A typed table whose types are the alternatives of a variant is
// described and read by describeTypes / readType below.
#include "../DeckDetail.hpp"
#include "spall/io/DeckKeys.hpp"

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace spall::io::keys {

// What a number must be: "> 0", "[0, 1]", "> room_temperature" (another key of the same table,
// read before this one).
struct Bound {
  enum class Kind { Any, Above, AtLeast, Below, AtMost, Closed, OpenClosed, Open };
  Kind kind = Kind::Any;
  double lo = 0.0, hi = 0.0;
  std::string_view loKey{};        // lo is this key's value...
  const double* loValue = nullptr; // ...read from here when checked
  std::string_view hiKey{};        // the same for hi
  const double* hiValue = nullptr;
  bool holds(double v) const;
  std::string text() const;
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
inline Bound above(std::string_view key, const double& value) {
  return {Bound::Kind::Above, 0.0, 0.0, key, &value};
}
// (lo, hi), each end another key's value or (lo) a number.
inline Bound between(std::string_view loKey, const double& lo, std::string_view hiKey,
                     const double& hi) {
  return {Bound::Kind::Open, 0.0, 0.0, loKey, &lo, hiKey, &hi};
}
inline Bound between(double lo, std::string_view hiKey, const double& hi) {
  return {Bound::Kind::Open, lo, 0.0, {}, nullptr, hiKey, &hi};
}

// The default of a key: `required` (the deck must give it), `off` (absent leaves the
// parameter's own value, meaning the feature is off: "none" in the reference), or a value.
struct Required {};
inline constexpr Required required{};
struct Off {};
inline constexpr Off off{};

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
  void flag(std::string_view key, bool&, bool fallback, std::string_view meaning) {
    row(key, "boolean", fallback ? "true" : "false", "", "", meaning);
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E&, const NameTable<E, N>& names, E fallback,
              std::string_view meaning) {
    row(key, oneOf(names.names()), quoted(names(fallback)), "", "", meaning);
  }
  // A condition over several keys, checked after them; its text joins `key`'s bound, `why` is
  // for the reader's message.
  void rule(std::string_view key, std::string_view text, std::string_view why, bool, double);

  KeySection take() { return std::move(section_); }
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
  explicit Read(const deck_detail::TableReader& r) : r_(r) {}

  void section(std::string_view, std::string_view) {}
  void number(std::string_view key, double& v, Required, std::string_view unit, Bound b,
              std::string_view) {
    v = r_.required(r_.number(key), key);
    check(key, v, unit, b);
  }
  void number(std::string_view key, double& v, double fallback, std::string_view unit, Bound b,
              std::string_view) {
    v = r_.number(key).value_or(fallback);
    check(key, v, unit, b);
  }
  void number(std::string_view key, double& v, Off, std::string_view unit, Bound b,
              std::string_view) {
    if (const auto given = r_.number(key)) {
      v = *given;
      check(key, v, unit, b);
    }
  }
  void number(std::string_view key, std::optional<double>& v, Off, std::string_view unit, Bound b,
              std::string_view) {
    v = r_.number(key);
    if (v) check(key, *v, unit, b);
  }
  void flag(std::string_view key, bool& v, bool fallback, std::string_view) {
    v = r_.boolean(key).value_or(fallback);
  }
  template <class E, std::size_t N>
  void choice(std::string_view key, E& v, const NameTable<E, N>& names, E fallback,
              std::string_view) {
    v = r_.choice(key, names, fallback);
  }
  void rule(std::string_view key, std::string_view text, std::string_view why, bool ok,
            double got) const;

private:
  void check(std::string_view key, double v, std::string_view unit, const Bound& b) const;
  const deck_detail::TableReader& r_;
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

// The material's models read from their tables (src/io/keys/*Keys.cpp), `type` already
// checked against the table's types.
materials::Eos readEos(const deck_detail::TableReader& r, std::string_view type,
                       double& minPressure);
StrengthModel readStrength(const deck_detail::TableReader& r, std::string_view type);
DamageModel readDamage(const deck_detail::TableReader& r, std::string_view type);
void readPorosity(const deck_detail::TableReader& r, PorosityConfig& c);

} // namespace spall::io::keys
