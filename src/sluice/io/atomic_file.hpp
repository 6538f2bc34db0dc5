// Files appear complete or not at all: everything is written to a temporary name in the same
// directory and renamed over the final name once fully written and flushed.
#pragma once

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sluice {

// An output that could not be written (unwritable directory, full disk, ...). The message names the
// file and the reason.
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path final_path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();  // removes the temporary file if commit() was not reached

  void write(const void* data, std::size_t bytes);
  void write(std::string_view text) { write(text.data(), text.size()); }
  // Flushes, syncs and renames to the final name.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& what);

  std::filesystem::path final_path_;
  std::filesystem::path temp_path_;
  std::FILE* file_ = nullptr;
};

void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// Creates a directory (and parents), with a clear error if it cannot.
void create_directories_or_throw(const std::filesystem::path& dir);

// Reads a whole file, or throws IoError naming it.
std::string read_file(const std::filesystem::path& path);

// Removes the temporary files (`<name>.tmp<pid>`) that a killed process left in `dir`, when the
// process that wrote them is gone. Returns how many were removed; never throws.
std::size_t remove_stale_temp_files(const std::filesystem::path& dir);

}  // namespace sluice
