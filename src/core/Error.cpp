#include "spall/core/Error.hpp"

namespace spall {

std::string DeckError::formatted() const {
  std::string s = where_.file.empty() ? std::string("deck") : where_.file;
  if (where_.line > 0) {
    s += ":" + std::to_string(where_.line) + ":" +
         std::to_string(where_.column > 0 ? where_.column : 1);
  }
  return s + ": error: " + what();
}

} // namespace spall
