// Freed memory kept in the process for the next simulation. A fit
// simulates the same records thousands of times, each simulation
// allocating the same large buffers (a Jet trace of a 4 s record at 100 µs
// is megabytes). By default glibc hands blocks above its mmap threshold
// (128 kB at first) straight back to the kernel, and trims the heap's top
// above 128 kB, so the next simulation faults the same pages in again one
// by one: on the paper job 160,000 page faults and a third of the CPU time
// (8.5 s user and 1.9 s system against 6.6 s and 0.6 s with 22,000 faults
// kept; glibc's mallopt(3), M_TOP_PAD).
#ifndef COMMON_ALLOCATOR_H_
#define COMMON_ALLOCATOR_H_

namespace axis {

// Sets glibc's top pad to 64 MB: the heap grows, and is trimmed, 64 MB at
// a time, so that freed blocks are reused by the next allocation of their
// size instead of being returned to the kernel (setting it also stops
// glibc's dynamic raising of the mmap threshold; a higher mmap or trim
// threshold alone helped no more, or made it worse: 174,000 and 254,000
// faults). Call once at the
// start of a program, before it starts threads (each front end does:
// apps/, python/). Never throws; without glibc it does nothing.
void KeepFreedMemory();

}  // namespace axis

#endif  // COMMON_ALLOCATOR_H_
