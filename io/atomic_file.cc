#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <system_error>

namespace axis {
namespace {

std::string ErrnoText(int err) { return std::generic_category().message(err); }

}  // namespace

void WriteFileAtomic(const std::string& path, const std::string& contents) {
  static std::atomic<unsigned> counter{0};
  const std::string prefix =
      path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + ".";
  std::string temp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp = prefix + std::to_string(counter++);
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    throw std::runtime_error(path +
                             ": cannot write: cannot create the "
                             "temporary file '" +
                             temp + "': " + ErrnoText(errno));
  }
  // Closes (if still open) and removes the temporary, then throws.
  auto fail = [&](const std::string& what, int err) {
    if (fd >= 0) ::close(fd);
    ::unlink(temp.c_str());
    throw std::runtime_error(path + ": cannot write: " + what + ": " +
                             ErrnoText(err));
  };
  const char* data = contents.data();
  size_t left = contents.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("writing '" + temp + "'", errno);
    }
    data += n;
    left -= static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0) fail("flushing '" + temp + "'", errno);
  const int closed = ::close(fd);
  fd = -1;
  if (closed != 0) fail("closing '" + temp + "'", errno);
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    fail("renaming '" + temp + "' over it", errno);
  }
}

void CheckOutputFile(const std::string& path) {
  const std::string expected =
      ": expected an output file (a path in an existing folder this process may write into), "
      "got ";
  if (path.empty()) throw std::invalid_argument("''" + expected + "an empty path");
  if (path.back() == '/') {
    throw std::invalid_argument(path + expected + "a folder path (ending in '/')");
  }
  struct stat info;
  if (::lstat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    throw std::invalid_argument(path + expected + "a folder");
  }
  const size_t slash = path.find_last_of('/');
  const std::string folder =
      slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  if (::stat(folder.c_str(), &info) != 0) {
    throw std::invalid_argument(path + expected + "'" + folder + "', a folder that does not exist");
  }
  if (!S_ISDIR(info.st_mode)) {
    throw std::invalid_argument(path + expected + "'" + folder + "', which is not a folder");
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw std::invalid_argument(path + expected + "'" + folder +
                                "', a folder that cannot be written into");
  }
}

}  // namespace axis
