#pragma once
// Append-only CSV files written by rank 0 (history.csv, probes.csv). Rows are buffered and
// flushed at most every `flushSeconds` of wall time, and always on close, so a long run pays
// little for I/O while a killed run still leaves all but the last moments on disk.
#include <chrono>
#include <cstdio>
#include <string>

namespace spall::io {

class CsvLog {
public:
  CsvLog() = default;
  CsvLog(const std::string& path, const std::string& header, double flushSeconds = 2.0);
  // Continues an existing file (a restart); writes the header only if the file is new.
  static CsvLog append(const std::string& path, const std::string& header,
                       double flushSeconds = 2.0);
  ~CsvLog();
  CsvLog(CsvLog&&) noexcept;
  CsvLog& operator=(CsvLog&&) noexcept;
  CsvLog(const CsvLog&) = delete;
  CsvLog& operator=(const CsvLog&) = delete;

  bool open() const { return file_ != nullptr; }
  void row(const std::string& line);
  void flush();

private:
  std::FILE* file_ = nullptr;
  std::string path_;
  double flushSeconds_ = 2.0;
  std::chrono::steady_clock::time_point lastFlush_;
};

} // namespace spall::io
