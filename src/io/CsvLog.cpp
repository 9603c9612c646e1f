#include "spall/io/CsvLog.hpp"

#include "spall/core/Error.hpp"

#include <cerrno>
#include <cstring>
#include <utility>

namespace spall::io {

CsvLog::CsvLog(const std::string& path, const std::string& header, double flushSeconds)
    : path_(path), flushSeconds_(flushSeconds), lastFlush_(std::chrono::steady_clock::now()) {
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw RunError("cannot write " + path + ": " + std::strerror(errno));
  row(header);
  flush();
}

CsvLog CsvLog::append(const std::string& path, const std::string& header, double flushSeconds) {
  std::FILE* existing = std::fopen(path.c_str(), "r");
  if (!existing) return CsvLog(path, header, flushSeconds);
  std::fclose(existing);
  CsvLog log;
  log.path_ = path;
  log.flushSeconds_ = flushSeconds;
  log.lastFlush_ = std::chrono::steady_clock::now();
  log.file_ = std::fopen(path.c_str(), "a");
  if (!log.file_) throw RunError("cannot append to " + path + ": " + std::strerror(errno));
  return log;
}

CsvLog::~CsvLog() {
  if (file_) std::fclose(file_);
}

CsvLog::CsvLog(CsvLog&& o) noexcept {
  *this = std::move(o);
}
CsvLog& CsvLog::operator=(CsvLog&& o) noexcept {
  std::swap(file_, o.file_);
  std::swap(path_, o.path_);
  flushSeconds_ = o.flushSeconds_;
  lastFlush_ = o.lastFlush_;
  return *this;
}

void CsvLog::row(const std::string& line) {
  if (!file_) return;
  if (std::fputs(line.c_str(), file_) < 0 || std::fputc('\n', file_) == EOF)
    throw RunError("write failed on " + path_ + ": " + std::strerror(errno));
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - lastFlush_).count() > flushSeconds_) {
    flush();
    lastFlush_ = now;
  }
}

void CsvLog::flush() {
  if (file_ && std::fflush(file_) != 0)
    throw RunError("write failed on " + path_ + ": " + std::strerror(errno));
}

} // namespace spall::io
