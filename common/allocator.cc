#include "common/allocator.h"

#include <cstdlib>  // <features.h>: __GLIBC__

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace axis {

void KeepFreedMemory() {
#if defined(__GLIBC__)
  mallopt(M_TOP_PAD, 64 * 1024 * 1024);
  // The largest value glibc accepts on 64-bit (DEFAULT_MMAP_THRESHOLD_MAX);
  // mallopt leaves the threshold as it was where it refuses the value.
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
#endif
}

}  // namespace axis
