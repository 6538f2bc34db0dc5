#include "sluice/io/directory_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>

#include <fmt/format.h>

#include "sluice/case/value_text.hpp"
#include "sluice/io/atomic_file.hpp"

namespace sluice {

namespace {

// What the holder wrote, on one line, escaped (text from another process reaches the terminal).
std::string holder_of(int fd) {
  char buffer[512];
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  if (n <= 0) return "another sluice process";
  std::string text(buffer, static_cast<std::size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return printable(text);
}

}  // namespace

DirectoryLock::DirectoryLock(const std::filesystem::path& dir, const std::string& what) : path_(dir / file_name) {
  // The holder removes the file when it lets go. A process that opened the file just before that
  // holds a lock on a removed file: it sees that the name now leads elsewhere (or nowhere) and tries
  // again.
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw IoError(fmt::format("{}: cannot create ({})", path_.string(), std::strerror(errno)));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      if (error == EWOULDBLOCK) {
        const std::string holder = holder_of(fd_);
        ::close(fd_);
        fd_ = -1;
        throw IoError(fmt::format(
            "{}: the output directory is in use by {}; wait for that run to finish or stop it, or write to another "
            "directory (-o)",
            dir.string(), holder));
      }
      // No locks on this file system (ENOLCK, EINVAL): carry on without one.
      ::close(fd_);
      fd_ = -1;
      return;
    }
    struct stat held {}, named {};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino)
      break;
    ::close(fd_);
  }
  char host[256] = "?";
  ::gethostname(host, sizeof host - 1);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char started[64] = "";
  std::tm utc{};
  if (::gmtime_r(&now, &utc) != nullptr) std::strftime(started, sizeof started, "%Y-%m-%d %H:%M:%S UTC", &utc);
  const std::string text =
      fmt::format("'{}' (process {} on {}, started {})\n", what, static_cast<long>(::getpid()), host, started);
  // The description is a courtesy for the message of a refused second run: a failure to write it
  // does not stop this one.
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, text.data(), text.size(), 0) < 0) return;
}

DirectoryLock::~DirectoryLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still holding the lock (see the constructor)
  ::close(fd_);
}

}  // namespace sluice
