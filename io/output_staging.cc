#include "io/output_staging.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "io/atomic_file.h"
#include "io/interrupt.h"

namespace axis {
namespace {
namespace fs = std::filesystem;
}  // namespace

void CheckOutputDirectory(const std::string& dir, bool staged) {
  std::error_code ec;
  fs::path target = fs::absolute(fs::path(dir), ec).lexically_normal();
  if (ec) target = fs::path(dir).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();  // "out/" → "out"
  const std::string expected =
      ": expected an output directory (an existing folder, or a path whose existing part is a "
      "folder this process may write into), got ";
  // `p` must be a folder this process may write into, if it exists.
  const auto check = [&](const fs::path& p) {
    if (!fs::exists(p, ec)) return;
    if (!fs::is_directory(p, ec)) {
      throw std::invalid_argument(dir + expected + "'" + p.string() + "', an existing file");
    }
    if (::access(p.c_str(), W_OK | X_OK) != 0) {
      throw std::invalid_argument(dir + expected + "'" + p.string() +
                                  "', a folder that cannot be written into");
    }
  };
  // The folder itself, if it exists (the outputs move into it), and the
  // nearest existing one above it (the staging folder is made beside it,
  // MakeStagingDirectory, with any missing parents).
  check(target);
  if (!staged && fs::exists(target, ec)) return;  // written into directly
  fs::path above = target.parent_path();
  while (!above.empty() && !fs::exists(above, ec) && above != above.parent_path()) {
    above = above.parent_path();
  }
  check(above);
}

bool IsOutputName(const std::string& name) {
  if (name.empty()) return false;
  for (char ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-' && ch != '.') {
      return false;
    }
  }
  return true;
}

std::vector<std::string> RemoveStaleStagingDirectories(const std::string& dir) {
  fs::path target = fs::path(dir);
  if (!target.has_filename()) target = target.parent_path();  // "out/" → "out"
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".partial.";
  std::vector<std::string> removed;
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec) return removed;
  for (const fs::directory_entry& entry : it) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) {
      continue;
    }
    const long pid = std::stol(digits);
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    // kill(pid, 0): ESRCH when no such process exists; EPERM means it
    // runs under another user, so it is alive.
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code remove_ec;
    if (!entry.is_directory(remove_ec)) continue;
    fs::remove_all(entry.path(), remove_ec);
    if (!remove_ec) removed.push_back(entry.path().string());
  }
  std::sort(removed.begin(), removed.end());
  return removed;
}

std::string MakeStagingDirectory(const std::string& dir) {
  fs::path target = fs::path(dir);
  if (!target.has_filename()) target = target.parent_path();  // "out/" → "out"
  const fs::path staging =
      target.string() + ".partial." + std::to_string(static_cast<long>(::getpid()));
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  fs::remove_all(staging, ec);
  ec.clear();
  fs::create_directory(staging, ec);
  if (ec) {
    throw std::runtime_error(staging.string() +
                             ": cannot create the staging folder for the outputs: " +
                             ec.message());
  }
  return staging.string();
}

namespace {

// Writes the list of `folder`'s entries (sorted, without the list itself)
// into `folder`/kOutputList and into each subfolder the same way; returns
// the names.
std::vector<std::string> WriteOutputLists(const fs::path& folder) {
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name == kOutputList) continue;
    names.push_back(name);
    std::error_code ec;
    if (entry.is_directory(ec)) WriteOutputLists(entry.path());
  }
  std::sort(names.begin(), names.end());
  std::string list;
  for (const std::string& name : names) list += name + "\n";
  WriteFileAtomic((folder / kOutputList).string(), list);
  return names;
}

// Removes the outputs an earlier run listed in `folder`/kOutputList that
// are not in `keep` (sorted): a file or link itself; a folder through its
// own list, then the folder if nothing else is left in it, so a file the
// user put there stays. Names with a path separator or "." / ".." are not
// outputs (a list edited by hand). Throws std::runtime_error naming what
// cannot be removed.
void RemoveEarlierOutputs(const fs::path& folder, const std::vector<std::string>& keep) {
  std::ifstream old_list(folder / kOutputList);
  for (std::string name; std::getline(old_list, name);) {
    if (name.empty() || name == "." || name == ".." || name == kOutputList ||
        name.find('/') != std::string::npos ||
        std::binary_search(keep.begin(), keep.end(), name)) {
      continue;
    }
    const fs::path p = folder / name;
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(p, ec))) {
      RemoveEarlierOutputs(p, {});
      fs::remove(p / kOutputList, ec);
      ec.clear();
      if (fs::is_empty(p, ec) && !ec) fs::remove(p, ec);
    } else {
      fs::remove(p, ec);
    }
    if (ec) {
      throw std::runtime_error(p.string() + ": cannot remove an earlier run's output: " +
                               ec.message());
    }
  }
}

}  // namespace

void CommitStagingDirectory(const std::string& staging, const std::string& dir) {
  std::error_code ec;
  // The lists of this run's outputs, in the staging folders so they move
  // with them.
  const std::vector<std::string> names = WriteOutputLists(staging);
  if (!fs::exists(dir, ec)) {
    fs::rename(staging, dir, ec);
    if (ec) {
      throw std::runtime_error(dir + ": cannot move the outputs from '" + staging +
                               "' into place: " + ec.message());
    }
    return;
  }
  if (!fs::is_directory(dir, ec)) {
    throw std::runtime_error(dir + ": cannot create the output directory: "
                             "exists and is not a directory");
  }
  RemoveEarlierOutputs(dir, names);
  for (const fs::directory_entry& entry : fs::directory_iterator(staging)) {
    const fs::path to = fs::path(dir) / entry.path().filename();
    if (entry.is_directory(ec) && fs::is_directory(to, ec)) {
      // A subfolder of outputs (a benchmark criterion's run) merges the same way.
      CommitStagingDirectory(entry.path().string(), to.string());
      continue;
    }
    fs::rename(entry.path(), to, ec);
    if (ec) {
      throw std::runtime_error(to.string() + ": cannot move the output from '" +
                               entry.path().string() + "': " + ec.message());
    }
  }
  fs::remove_all(staging, ec);
}

std::vector<std::string> WriteStaged(
    const std::string& dir,
    const std::function<void(const std::string&, std::vector<std::string>*)>& write) {
  std::vector<std::string> warnings;
  for (const std::string& stale : RemoveStaleStagingDirectories(dir)) {
    warnings.push_back("removed " + stale +
                       ", the staging folder of an earlier run whose process is gone (it "
                       "ended before moving its outputs into place)");
  }
  DeferInterrupts defer;
  const std::string staging = MakeStagingDirectory(dir);
  try {
    write(staging, &warnings);
    CommitStagingDirectory(staging, dir);
    // Warnings name the files where they end up, not the staging folder.
    for (std::string& w : warnings) {
      for (size_t at = w.find(staging); at != std::string::npos;
           at = w.find(staging, at + dir.size())) {
        w.replace(at, staging.size(), dir);
      }
    }
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove_all(staging, ec);
    throw;
  }
  defer.Committed();
  return warnings;
}

}  // namespace axis
