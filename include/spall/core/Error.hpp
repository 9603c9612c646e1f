#pragma once
// Errors that cross layers. A DeckError carries the TOML position of the offending value and maps
// to exit code 2 (nothing run, nothing written); a RunError is a failure while running (exit 1)
// and names the particle, field and step where one is involved.
#include <stdexcept>
#include <string>

namespace spall {

struct SourceLocation {
  std::string file; // deck path, or "--set KEY=VALUE" for a command-line override
  int line = 0;     // 1-based; 0 when unknown
  int column = 0;   // 1-based; 0 when unknown
};

class DeckError : public std::runtime_error {
public:
  DeckError(SourceLocation where, const std::string& message)
      : std::runtime_error(message), where_(std::move(where)) {}
  const SourceLocation& where() const { return where_; }
  // "FILE:LINE:COLUMN: error: MESSAGE" (INTERFACE.md, "Bad input").
  std::string formatted() const;

private:
  SourceLocation where_;
};

// A usage error that is not tied to a deck position (bad CLI flags, existing output directory).
class UsageError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

class RunError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

} // namespace spall
