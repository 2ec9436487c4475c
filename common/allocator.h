// Freed memory kept in the process for the next simulation. A fit
// simulates the same records thousands of times, each simulation
// allocating the same large buffers (a Jet trace of a 4 s record at 100 µs
// is megabytes). By default glibc hands blocks above its mmap threshold
// (128 kB at first) straight back to the kernel, and trims the heap's top
// above 128 kB, so the next simulation faults the same pages in again one
// by one: on the paper job 160,000 page faults and a third of the CPU time
// (8.5 s user and 1.9 s system against 6.6 s and 0.6 s with 22,000 faults
// kept; glibc's mallopt(3), M_TOP_PAD, M_MMAP_THRESHOLD).
#ifndef COMMON_ALLOCATOR_H_
#define COMMON_ALLOCATOR_H_

namespace axis {

// Sets glibc's top pad to 64 MB (the heap grows, and is trimmed, 64 MB at
// a time) and its mmap threshold to its maximum, 32 MB on 64-bit systems
// (DEFAULT_MMAP_THRESHOLD_MAX), so that a freed block is reused by the next
// allocation of its size instead of being returned to the kernel. Both are
// needed: setting the top pad stops glibc's dynamic raising of the mmap
// threshold, which then stays at 128 kB, and every trace of a 4 s record
// (its Jet buffers 4–5 MB) is mapped and unmapped anew. With the top pad
// alone, a discovery run on two 4 s records (the independent square and
// sweep job, --discover) took 7.7 million page faults and 18 s of system
// time in 93 s; with both, 0.25 million and 0.8 s. A block above 32 MB is
// still mapped on its own. Call once at the start of a program, before it
// starts threads (each front end does: apps/, python/, bench/). Never
// throws; without glibc it does nothing.
void KeepFreedMemory();

}  // namespace axis

#endif  // COMMON_ALLOCATOR_H_
