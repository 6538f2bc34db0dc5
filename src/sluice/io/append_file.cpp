#include "sluice/io/append_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "sluice/io/atomic_file.hpp"

namespace sluice {

namespace {

// Writes all of `bytes` at `offset`; returns 0, or the errno of the write that failed.
int write_all_at(int fd, std::string_view bytes, std::uint64_t offset) {
  while (!bytes.empty()) {
    const ssize_t n = ::pwrite(fd, bytes.data(), bytes.size(), static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : ENOSPC;
    bytes.remove_prefix(static_cast<std::size_t>(n));
    offset += static_cast<std::uint64_t>(n);
  }
  return 0;
}

}  // namespace

AppendFile::AppendFile(std::filesystem::path path, std::string header, std::string footer)
    : path_(std::move(path)), header_(std::move(header)), footer_(std::move(footer)) {}

AppendFile::AppendFile(AppendFile&& other) noexcept
    : path_(std::move(other.path_)), header_(std::move(other.header_)), footer_(std::move(other.footer_)),
      fd_(std::exchange(other.fd_, -1)), size_(other.size_) {}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendFile::fail(const std::string& what, int error) {
  throw IoError(fmt::format("{}: {} ({})", path_.string(), what, std::strerror(error)));
}

void AppendFile::open_existing() {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) fail("cannot open", errno);
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  if (end < 0) fail("cannot open", errno);
  size_ = static_cast<std::uint64_t>(end);
}

void AppendFile::resume(const std::string& content) {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (content.empty()) return;
  std::error_code ec;
  if (!std::filesystem::exists(path_, ec) || read_file(path_) != content) write_file_atomic(path_, content);
  open_existing();
}

void AppendFile::append(std::string_view records) {
  if (fd_ < 0) {
    std::string content = header_;
    content += records;
    content += footer_;
    write_file_atomic(path_, content);
    open_existing();
    return;
  }
  if (records.empty()) return;
  const std::uint64_t at = size_ - footer_.size();
  std::string bytes(records);
  bytes += footer_;
  if (const int error = write_all_at(fd_, bytes, at); error != 0) {
    // Put the file back as it was: cut what was written past its old end, and restore the footer,
    // whose bytes lie inside the old size and so need no new space.
    if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0 || write_all_at(fd_, footer_, at) != 0)
      fail(fmt::format("cannot write ({}), nor undo the part written", std::strerror(error)), errno);
    fail("cannot write", error);
  }
  size_ = at + bytes.size();
}

void AppendFile::sync() {
  if (fd_ >= 0 && ::fsync(fd_) != 0) fail("cannot sync", errno);
}

}  // namespace sluice
