#include "sim/files/directory_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "sim/experiment/config_error.h"

namespace mcref {

namespace fs = std::filesystem;

DirectoryLock::DirectoryLock(const std::string& dir, const std::string& output, const std::string& flag) : dir_(dir) {
  // The directory may be removed and made again by the holder between our
  // open and our lock: a lock on a removed directory guards nothing, so the
  // lock must be on what the path names once it is held.
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error(dir + ": cannot create the directory: " + ec.message());
    const int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) {
      if (errno == ENOENT) continue;
      throw std::runtime_error(dir + ": cannot open the directory: " + std::strerror(errno));
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      close(fd);
      if (e == EWOULDBLOCK)
        throw ConfigError(output, flag, "another process is writing this output (it holds the lock on " + dir +
                                            "); wait for it to end, or choose another " + flag);
      // A file system without flock (Lustre mounted without -o flock: ENOSYS):
      // the run goes on unguarded, and says so.
      std::fprintf(stderr, "mcref: warning: %s: cannot lock the directory (%s); a second process given this output "
                   "would not be refused\n", dir.c_str(), std::strerror(e));
      return;
    }
    struct stat held {}, named {};
    if (fstat(fd, &held) == 0 && stat(dir.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino) {
      fd_ = fd;
      return;
    }
    close(fd);  // removed (and perhaps made again) meanwhile: lock what is there now
  }
  throw std::runtime_error(dir + ": cannot lock the directory: it keeps being removed");
}

DirectoryLock::~DirectoryLock() {
  std::error_code ec;
  if (fs::is_empty(dir_, ec) && !ec) fs::remove(dir_, ec);  // before unlocking: another process then makes its own
  if (fd_ >= 0) close(fd_);
}

}  // namespace mcref
