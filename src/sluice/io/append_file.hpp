// Files that grow by whole records (CSV rows, .pvd entries) during a run, so that writing a record
// costs the same at the end of a run as at its start.
//
// The file is created complete (header, first records, footer) under a temporary name and renamed;
// after that each batch of records goes in with one write at the end, over the footer if the file has
// one (the .pvd's closing tags) and followed by it again. A write that fails (full disk, file-size
// limit) is undone, so the file keeps only whole records. Only a kill inside the write itself can
// leave a cut-off last record: the write is one system call, and the kernel stops a killed process's
// write only between two pages of it (never inside a write that stays within one page, as a .pvd
// entry or a diagnostics row mostly does). A restart cuts such a record off again (csv_rows_until, or
// the .pvd rebuilt from the frames on disk).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace sluice {

class AppendFile {
 public:
  // A file that starts with `header` and ends with `footer` ("" for none); nothing is written yet.
  AppendFile(std::filesystem::path path, std::string header, std::string footer = {});
  AppendFile(AppendFile&& other) noexcept;
  AppendFile& operator=(AppendFile&&) = delete;
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;
  ~AppendFile();

  // Continues from `content`, the whole file as it should be now (header and footer included; "" for
  // no file yet): what a restart keeps of the file on disk. The file is replaced (atomically) only if
  // it holds something else.
  void resume(const std::string& content);

  // Adds whole records (each ending in '\n') before the footer. The first call creates the file, header
  // and footer included, even with no records.
  void append(std::string_view records);

  // Makes what was appended durable (fsync), e.g. before a checkpoint that relies on it.
  void sync();

 private:
  void open_existing();
  [[noreturn]] void fail(const std::string& what, int error);

  std::filesystem::path path_;
  std::string header_;
  std::string footer_;
  int fd_ = -1;             // open once the file exists
  std::uint64_t size_ = 0;  // bytes in the file, footer included
};

}  // namespace sluice
