#pragma once
// Errors that cross layers. A DeckError carries the TOML position of the offending value and maps
// to exit code 2 (nothing run, nothing written); a RunError is a failure while running (exit 1)
// and names the particle, field and step where one is involved.
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace spall {

struct SourceLocation {
  std::string file; // deck path, or "--set KEY=VALUE" for a command-line override
  int line = 0;     // 1-based; 0 when unknown
  int column = 0;   // 1-based; 0 when unknown
};

// A value a deck may hold but probably did not mean ("density 17.6 kg/m^3 for a solid: g/cm^3?").
struct DeckWarning {
  SourceLocation where;
  std::string message;
  // "FILE:LINE:COLUMN: warning: MESSAGE".
  std::string formatted() const;
};

class DeckError : public std::runtime_error {
public:
  DeckError(SourceLocation where, const std::string& message)
      : std::runtime_error(message), where_(std::move(where)) {}
  const SourceLocation& where() const { return where_; }
  // "FILE:LINE:COLUMN: error: MESSAGE" (docs/reference.md, "Bad input").
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
  explicit RunError(const std::string& message, bool collective = false)
      : std::runtime_error(message), collective_(collective) {}
  // Raised with the same message on every rank: rank 0 alone prints it.
  bool isCollective() const { return collective_; }

private:
  bool collective_;
};

// One particle's state, as a failure or a warning reports it: values that went non-finite, or
// the particle that sets (or collapsed) the time step. The owner rank fills it; every rank holds
// the same copy (it travels as bytes).
struct ParticleReport {
  enum class Kind : std::int32_t { NonFinite, Collapse, Energy };
  Kind kind = Kind::NonFinite;
  std::uint64_t id = 0;
  std::int32_t material = -1, body = -1, neighbors = 0;
  std::int64_t step = 0;       // the step whose result is bad (NonFinite) or too stiff (Collapse)
  double time = 0.0, dt = 0.0; // dt: the collapsed step (Collapse)
  std::array<double, 3> x{}, v{};
  double rho = 0.0, h = 0.0, p = 0.0, cs = 0.0, e = 0.0;
};

// A RunError raised alike on every rank, carrying the fault, so that the run loop can rewind
// to its last good state and explain what happened to that particle.
class StepFailure : public RunError {
public:
  StepFailure(const std::string& message, const ParticleReport& fault, std::string fields)
      : RunError(message, true), fault_(fault), fields_(std::move(fields)) {}
  const ParticleReport& fault() const { return fault_; }
  // The fields that went bad, comma-separated (NonFinite).
  const std::string& fields() const { return fields_; }

private:
  ParticleReport fault_;
  std::string fields_;
};

} // namespace spall
