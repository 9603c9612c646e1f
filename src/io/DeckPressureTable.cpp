// A pressure boundary's table (DeckDetail.hpp): rows [time, pressure], finite, times >= 0 and
// rising; each error at the row or value it rejects.
#include "DeckDetail.hpp"

#include <cmath>

namespace spall::io::deck_detail {

std::vector<std::pair<double, double>> readPressureTable(const TableReader& r) {
  std::vector<std::pair<double, double>> table;
  const toml::array* rows = r.table().get_as<toml::array>("pressure");
  if (!rows) r.missing("pressure");
  const std::string form = r.quoted("pressure") + " is a table of [time, pressure] rows (s, Pa)";
  if (rows->empty()) r.fail("pressure", form + ": it has none");
  for (const toml::node& node : *rows) {
    const toml::array* row = node.as_array();
    if (!row || row->size() != 2) throw DeckError(r.whereNode(node), form);
    double tp[2];
    for (std::size_t c = 0; c < 2; ++c) {
      const auto x = (*row)[c].value<double>();
      if (!x || !std::isfinite(*x))
        throw DeckError(r.whereNode((*row)[c]), form + ": this is not a finite number");
      tp[c] = *x;
    }
    if (tp[0] < 0.0) throw DeckError(r.whereNode((*row)[0]), form + ": times are >= 0");
    if (!table.empty() && !(tp[0] > table.back().first))
      throw DeckError(r.whereNode((*row)[0]), form + ": times must increase from row to row (" +
                                                  formatNumber(tp[0]) + " after " +
                                                  formatNumber(table.back().first) + ")");
    table.emplace_back(tp[0], tp[1]);
  }
  return table;
}

} // namespace spall::io::deck_detail
