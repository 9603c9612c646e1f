#include "spall/io/FTable.hpp"

#include "spall/core/Error.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace spall::io {

namespace {

struct Token {
  std::string text;
  int column = 0; // 1-based
};

std::vector<Token> tokens(const std::string& line) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < line.size()) {
    if (line[i] == '#') break;
    if (std::isspace(static_cast<unsigned char>(line[i]))) {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i])) && line[i] != '#')
      ++i;
    out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

} // namespace

FTable readFTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError("cannot read the F-table " + path);
  FTable table;
  table.path = path;
  std::string line;
  int lineNo = 0;
  std::size_t width = 0;
  const auto fail = [&](int line, int column, const std::string& message) {
    throw DeckError({path, line, column}, message);
  };
  while (std::getline(in, line)) {
    ++lineNo;
    const auto tok = tokens(line);
    if (tok.empty()) continue;
    if (tok.size() != 10 && tok.size() != 14)
      fail(lineNo, tok.front().column,
           "an F-table row has 10 numbers (t and F11 ... F33) or 14 (and theta_deg ax ay az), "
           "this one has " +
               std::to_string(tok.size()));
    if (width != 0 && tok.size() != width)
      fail(lineNo, tok.front().column,
           "every row of an F-table has the same number of columns (the first had " +
               std::to_string(width) + ")");
    width = tok.size();
    double v[14];
    for (std::size_t k = 0; k < tok.size(); ++k) {
      const std::string& s = tok[k].text;
      const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v[k]);
      if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v[k]))
        fail(lineNo, tok[k].column, "'" + s + "' is not a finite number");
    }
    FTableRow row;
    row.t = v[0];
    row.line = lineNo;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) row.F(a, b) = v[1 + 3 * a + b];
    if (!(row.F.determinant() > 0.0))
      fail(lineNo, tok[1].column,
           "det F must be positive (the material cannot invert), got " +
               std::to_string(row.F.determinant()));
    if (width == 14) {
      row.thetaDeg = v[10];
      const Vec<3> axis(v[11], v[12], v[13]);
      if (!(axis.norm() > 0.0)) fail(lineNo, tok[11].column, "the rotation axis is zero");
      row.axis = axis.normalized();
    }
    if (!table.rows.empty() && !(row.t > table.rows.back().t))
      fail(lineNo, tok[0].column, "times must increase from row to row");
    table.rows.push_back(row);
  }
  if (table.rows.size() < 2)
    throw DeckError({path, lineNo, 0}, "an F-table needs at least two rows (a start and an end)");
  table.rotation = width == 14;
  return table;
}

} // namespace spall::io
