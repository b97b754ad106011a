// The front ends' setting of the C allocator (the tool and the viewer).
#pragma once

#if defined(__GLIBC__) && defined(__linux__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#endif

namespace osdmra::cli {

/// glibc hands blocks over 128 KiB to mmap and returns them to the system when freed,
/// so every large temporary (a level's arrays, a sparse matrix) is faulted in again
/// page by page; on a virtual machine a fault costs tens of microseconds, and the
/// decoding of a 153,602-vertex stream spent more time faulting than computing (33,000
/// faults, 0.59 s; 17,900 and 0.37 s with freed memory kept). The front ends keep
/// freed memory for reuse, and ask for transparent huge pages over the heap they grow
/// into (one fault per 2 MiB instead of per 4 KiB where the system grants them on
/// request, as Debian's default "madvise" does: the same decoding then faults 807 times
/// and takes 0.26 s instead of 0.35). The library leaves its host's allocator alone.
inline void keepFreedMemory() {
#if defined(__GLIBC__) && defined(__linux__)
  constexpr std::size_t kReserve = std::size_t{1} << 30;  // address space, not memory
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest threshold
  mallopt(M_TRIM_THRESHOLD, 2 << 30);   // beyond the reserve, which is kept
  mallopt(M_TOP_PAD, static_cast<int>(kReserve));
  // Grow the heap once (a block over what it has free, under the mmap threshold), by
  // the reserve beyond it, mark that range, and give the block back to the heap.
  void* grow = std::malloc(16 << 20);
  if (!grow) return;
  const auto from = (reinterpret_cast<std::uintptr_t>(grow) + kHuge - 1) & ~(kHuge - 1);
  const auto to = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(kHuge - 1);
  if (to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);
  std::free(grow);
#endif
}

}  // namespace osdmra::cli
