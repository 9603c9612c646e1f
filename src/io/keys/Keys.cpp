// The bounds, defaults and checks of Keys.hpp.
#include "Keys.hpp"

#include <fmt/format.h>

namespace spall::io::keys {

namespace {

std::string plain(double v) {
  return fmt::format("{}", v);
}

} // namespace

std::string tomlNumber(double v) {
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0"; // "1" would be a TOML integer
  return s;
}

bool Bound::holds(double v) const {
  const double a = loValue ? *loValue : lo, b = hiValue ? *hiValue : hi;
  switch (kind) {
  case Kind::Any:
    return true;
  case Kind::Above:
    return v > a;
  case Kind::AtLeast:
    return v >= a;
  case Kind::Below:
    return v < b;
  case Kind::AtMost:
    return v <= b;
  case Kind::Closed:
    return v >= a && v <= b;
  case Kind::OpenClosed:
    return v > a && v <= b;
  case Kind::ClosedOpen:
    return v >= a && v < b;
  case Kind::Open:
    return v > a && v < b;
  }
  return false;
}

std::string Bound::text() const {
  const std::string a = loKey.empty() ? plain(lo) : std::string(loKey);
  const std::string b = hiKey.empty() ? plain(hi) : std::string(hiKey);
  switch (kind) {
  case Kind::Any:
    return "";
  case Kind::Above:
    return "> " + a;
  case Kind::AtLeast:
    return ">= " + a;
  case Kind::Below:
    return "< " + b;
  case Kind::AtMost:
    return "<= " + b;
  case Kind::Closed:
    return "[" + a + ", " + b + "]";
  case Kind::OpenClosed:
    return "(" + a + ", " + b + "]";
  case Kind::ClosedOpen:
    return "[" + a + ", " + b + ")";
  case Kind::Open:
    return "(" + a + ", " + b + ")";
  }
  return "";
}

std::string Describe::oneOf(const std::vector<std::string_view>& names) {
  std::string s = "one of:";
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : " ") + std::string(names[i]);
  return s;
}

std::string Describe::quoted(std::string_view name) {
  return fmt::format("\"{}\"", name);
}

void Describe::rule(std::string_view key, std::string_view text, std::string_view, bool, double) {
  for (auto& k : section_.keys)
    if (k.name == key) {
      k.bounds += (k.bounds.empty() ? "" : "; ") + std::string(text);
      return;
    }
  throw std::logic_error("internal: a rule on '" + std::string(key) + "' before its key");
}

void Read::rule(std::string_view key, std::string_view text, std::string_view why, bool ok,
                double got) const {
  if (!ok)
    r_.fail(key, fmt::format("{} is {} in {}, and {} must hold: {}", r_.quoted(key),
                             deck_detail::formatNumber(got), r_.context().human, text, why));
}

void Read::check(std::string_view key, double v, std::string_view unit, const Bound& b) const {
  if (b.holds(v)) return;
  // A bound by other keys says their values: "> e_iv, e_iv = 2e6".
  std::string what = b.text();
  if (b.kind == Bound::Kind::Closed || b.kind == Bound::Kind::OpenClosed ||
      b.kind == Bound::Kind::ClosedOpen || b.kind == Bound::Kind::Open)
    what = "in " + what;
  if (b.loValue)
    what += ", " + std::string(b.loKey) + " = " + deck_detail::formatNumber(*b.loValue);
  if (b.hiValue)
    what += ", " + std::string(b.hiKey) + " = " + deck_detail::formatNumber(*b.hiValue);
  r_.check(false, key, unit.empty() ? what : what + " (" + std::string(unit) + ")", v);
}

} // namespace spall::io::keys
