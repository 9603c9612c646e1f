// The bounds, defaults and checks of Keys.hpp.
#include "Keys.hpp"

#include <cmath>
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

namespace {
// 1e5 rather than 100000: the plausible ranges span decades.
std::string decade(double v) {
  std::string s = fmt::format("{:.3g}", v);
  if (const auto e = s.find("e+"); e != std::string::npos)
    s = s.substr(0, e) + "e" + std::to_string(std::stoi(s.substr(e + 2)));
  return s;
}
} // namespace

std::string Bound::text() const {
  const std::string t = strictText();
  if (!plausible.set()) return t;
  std::string w = "warns";
  if (!plausible.low.empty())
    w += " below " + decade(plausible.lo) + " (" + std::string(plausible.low) + ")";
  if (!plausible.high.empty())
    w += std::string(plausible.low.empty() ? "" : " or") + " above " + decade(plausible.hi) + " (" +
         std::string(plausible.high) + ")";
  return t.empty() ? w : t + "; " + w;
}

std::string Bound::strictText() const {
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

void Read::plausible(std::string_view key, double v, std::string_view unit, const Bound& b) const {
  const Plausible& p = b.plausible;
  if (!p.set() || v == 0.0 || !std::isfinite(v)) return;
  const bool low = v < p.lo && !p.low.empty(), high = v > p.hi && !p.high.empty();
  if (!low && !high) return;
  const std::string u = unit.empty() ? std::string() : fmt::format(" {}", unit);
  r_.warn(key,
          fmt::format("{} = {}{} is {} {}{}: {}", r_.quoted(key), deck_detail::formatNumber(v), u,
                      low ? "below" : "above", decade(low ? p.lo : p.hi), u, low ? p.low : p.high));
}

void Read::check(std::string_view key, double v, std::string_view unit, const Bound& b) const {
  plausible(key, v, unit, b);
  if (b.holds(v)) return;
  // A bound by other keys says their values: "> e_iv, e_iv = 2e6".
  std::string what = b.strictText();
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
