#pragma once
#include <cstddef>
#include <string>

namespace spall::app {

// Resident set size now and its peak (VmRSS, VmHWM from /proc/self/status), in bytes.
std::size_t residentBytes();
std::size_t peakResidentBytes();
// Memory this process may still take: MemAvailable (/proc/meminfo), or the physical memory when
// that cannot be read.
std::size_t availableMemoryBytes();

struct BuildInfo {
  static const char* version();
  static const char* gitRevision();
  static const char* compiler();
  static const char* buildType();
};

std::string infoText(); // `spall info`

} // namespace spall::app
