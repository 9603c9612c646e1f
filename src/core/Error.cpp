#include "spall/core/Error.hpp"

namespace spall {

namespace {
std::string position(const SourceLocation& where) {
  std::string s = where.file.empty() ? std::string("deck") : where.file;
  if (where.line > 0)
    s += ":" + std::to_string(where.line) + ":" +
         std::to_string(where.column > 0 ? where.column : 1);
  return s;
}
} // namespace

std::string DeckWarning::formatted() const {
  return position(where) + ": warning: " + message;
}

std::string DeckError::formatted() const {
  return position(where_) + ": error: " + what();
}

} // namespace spall
