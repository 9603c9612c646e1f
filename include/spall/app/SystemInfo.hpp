#pragma once
#include <cstddef>
#include <string>

namespace spall::app {

// Resident set size now and its peak (VmRSS, VmHWM from /proc/self/status), in bytes.
std::size_t residentBytes();
std::size_t peakResidentBytes();

struct BuildInfo {
  static const char* version();
  static const char* gitRevision();
  static const char* compiler();
  static const char* buildType();
};

std::string infoText(); // `spall info`

} // namespace spall::app
