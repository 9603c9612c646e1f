// The deck as TOML text: floats in their shortest round-trip form (DeckDetail.hpp).
#include "DeckDetail.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <string>
#include <string_view>

namespace spall::io::deck_detail {

namespace {
// The end of a string starting at text[i] (a quote), past its closing quote(s).
std::size_t skipString(std::string_view text, std::size_t i) {
  const char q = text[i];
  const bool multi = text.substr(i, 3) == std::string(3, q);
  std::size_t j = i + (multi ? 3 : 1);
  while (j < text.size()) {
    if (q == '"' && text[j] == '\\') {
      j += 2;
      continue;
    }
    if (multi ? text.substr(j, 3) == std::string(3, q) : text[j] == q) return j + (multi ? 3 : 1);
    if (!multi && text[j] == '\n') return j; // unterminated: leave the rest alone
    ++j;
  }
  return j;
}

bool numberChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '+' || c == '-' ||
         c == '_';
}
} // namespace

std::string shortestFloats(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      const std::size_t end = skipString(text, i);
      out.append(text.substr(i, end - i));
      i = end;
      continue;
    }
    if (c == '#') {
      const std::size_t end = std::min(text.find('\n', i), text.size());
      out.append(text.substr(i, end - i));
      i = end;
      continue;
    }
    const bool starts = std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+';
    if (!starts || (i > 0 && numberChar(text[i - 1]))) {
      out += c;
      ++i;
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && numberChar(text[end])) ++end;
    const std::string token(text.substr(i, end - i));
    std::size_t after = end;
    while (after < text.size() && (text[after] == ' ' || text[after] == '\t')) ++after;
    const bool isKey = after < text.size() && (text[after] == '=' || text[after] == '.');
    const bool isFloat = token.find_first_of(".eE") != std::string::npos &&
                         token.find('_') == std::string::npos &&
                         token.find_first_of("xob") == std::string::npos;
    if (isFloat && !isKey) {
      char* stop = nullptr;
      const double v = std::strtod(token.c_str(), &stop);
      if (stop == token.c_str() + token.size() && std::isfinite(v)) {
        std::string s = fmt::format("{}", v);
        if (s.find_first_of(".e") == std::string::npos) s += ".0";
        if (std::strtod(s.c_str(), nullptr) == v) {
          out += s;
          i = end;
          continue;
        }
      }
    }
    out += token;
    i = end;
  }
  return out;
}

} // namespace spall::io::deck_detail
