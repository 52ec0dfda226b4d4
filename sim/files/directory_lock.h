#pragma once
// An exclusive lock on a working directory (a dataset's OUTPUT.parts/), so
// that a second process given the same output is refused at once instead of
// racing the first: both would rename their OUTPUT over the other's, and each
// removes the parts and temporaries it finds there. flock(2) on the
// directory itself: no lock file is left behind, and the kernel releases the
// lock when the process ends, however it ends.
#include <string>

namespace mcref {

class DirectoryLock {
 public:
  // Creates `dir` if missing and locks it. ConfigError naming `output` and
  // `dir` if another process holds the lock (flag: the option naming output).
  // Where the file system cannot lock (no flock), warns and goes on unlocked.
  DirectoryLock(const std::string& dir, const std::string& output, const std::string& flag);
  ~DirectoryLock();  // unlocks; removes `dir` if it is empty
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  std::string dir_;
  int fd_ = -1;
};

}  // namespace mcref
