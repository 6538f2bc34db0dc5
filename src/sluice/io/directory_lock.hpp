// One writer per output directory: a run (or a validation or convergence study) holds a lock on its
// output directory while it writes there, so that a second one started into the same directory is
// refused instead of mixing its frames, diagnostics and summary with the first's.
//
// The lock is an advisory lock (flock) on the file `.sluice.lock` in the directory, which also names
// the holder (process id, host, command, start time) for the refusal's message. The kernel releases
// it when the holder exits in any way (a crash, SIGKILL, the out-of-memory killer), so a lock left by
// a dead process is simply taken over. The holder removes the file when it is done; one left by a
// killed process means nothing once unlocked.
#pragma once

#include <filesystem>
#include <string>

namespace sluice {

class DirectoryLock {
 public:
  // Takes the lock of `dir` (which must exist) for `what` (e.g. "sluice run dam_break"), or throws
  // IoError naming the directory and the process that holds it. On a file system without locks, none
  // is taken (the run goes on as before locks existed).
  DirectoryLock(const std::filesystem::path& dir, const std::string& what);
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;
  ~DirectoryLock();

  static constexpr const char* file_name = ".sluice.lock";

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

}  // namespace sluice
