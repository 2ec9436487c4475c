// Files written whole or not at all: a temporary file in the same folder,
// flushed, then renamed over the target, so that a reader never sees a
// half-written file; and the check, before any work, that such a file can
// be written.
#ifndef IO_ATOMIC_FILE_H_
#define IO_ATOMIC_FILE_H_

#include <string>

namespace axis {

// Writes `contents` to `path` atomically: to a temporary file
// "<path>.tmp.<pid>.<n>" in the same directory (created with mode 0666 minus
// the umask), flushed to disk, then std::rename over `path` (replacing an
// existing file, or a symbolic link itself rather than its target). On any
// failure removes the temporary and throws std::runtime_error naming `path`
// and the system error. Never leaves a partial file at `path`: readers see
// either the old file or the complete new one.
void WriteFileAtomic(const std::string& path, const std::string& contents);

// Checks, before any work, that WriteFileAtomic can write `path`: a
// non-empty path that is not a folder (a symbolic link is replaced, not
// followed), in an existing folder this process may write into (the
// temporary file is made there). Throws std::invalid_argument "<path>:
// expected an output file (a path in an existing folder this process may
// write into), got …" naming the folder in the way, the missing folder or
// the one that cannot be written into.
void CheckOutputFile(const std::string& path);

}  // namespace axis

#endif  // IO_ATOMIC_FILE_H_
