// How freed memory goes back to the system, set once for the process.
//
// A step allocates temporaries of a few arrays' size (the pair loop's fluid counts, mDBC's compact
// fluid arrays, the leak checks' marks) and frees them before the next. With glibc's defaults the
// heap's top is given back to the system when 128 KB or more of it is free, and blocks of 128 KB or
// more are mapped and unmapped one by one, unless an earlier free of a large block happened to raise
// both limits; then every step faults its temporaries' pages in again, zeroed by the kernel, with
// the threads of a step queueing on the process's memory map. Measured: SPHERIC test 2 at 103k
// particles on two threads, 590 page faults a step from `sluice-bench-run` (whose set-up freed no
// large block) and none from `sluice run`, and two threads 1.24-1.40 times one thread's speed
// against 1.67 times.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <mutex>

namespace sluice {

// Keeps freed memory in the process: blocks up to 32 MiB (4M doubles, glibc's largest) come from the
// heap, and its top is given back only above 512 MiB free. The peak memory is unchanged; memory
// freed below it is reused by the next step instead of being returned and faulted in again.
inline void keep_freed_memory() {
#if defined(__GLIBC__)
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
  });
#endif
}

}  // namespace sluice
