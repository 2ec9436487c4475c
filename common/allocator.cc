#include "common/allocator.h"

#include <cstdlib>  // <features.h>: __GLIBC__

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace axis {

void KeepFreedMemory() {
#if defined(__GLIBC__)
  mallopt(M_TOP_PAD, 64 * 1024 * 1024);
#endif
}

}  // namespace axis
