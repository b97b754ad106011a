// The front ends' setting of the C allocator (the tool and the viewer).
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace osdmra::cli {

/// glibc hands blocks over 128 KiB to mmap and returns them to the system when freed,
/// so every large temporary (a level's arrays, a sparse matrix) is faulted in again
/// page by page; on a virtual machine a fault costs tens of microseconds, and the
/// decoding of a 153,602-vertex stream spent more time faulting than computing (33,000
/// faults, 0.59 s; 17,900 and 0.37 s with freed memory kept). The front ends keep
/// freed memory for reuse; the library leaves its host's allocator alone.
inline void keepFreedMemory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest threshold
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace osdmra::cli
