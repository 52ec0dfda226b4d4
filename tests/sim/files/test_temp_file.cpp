// sim/files/temp_file.h: temporaries are named <output>.tmp.<pid>, removed when
// not committed, removed by SIGINT/SIGTERM/SIGHUP while alive, and removed
// by the next writer of the same output once their process is gone.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sim/files/temp_file.h"

namespace fs = std::filesystem;
using namespace mcref;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("mcref_test_temp_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(TempFile, CommitRenamesAndDestructionWithoutCommitRemoves) {
  const fs::path d = scratch("commit");
  const std::string out = (d / "o.h5").string();
  {
    TempFile t(out);
    EXPECT_EQ(t.path(), out + ".tmp." + std::to_string(getpid()));
    std::ofstream(t.path()) << "data";
  }
  EXPECT_FALSE(fs::exists(out + ".tmp." + std::to_string(getpid())));
  EXPECT_FALSE(fs::exists(out));
  {
    TempFile t(out);
    std::ofstream(t.path()) << "data";
    t.commit();
  }
  EXPECT_TRUE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(d) == false && std::distance(fs::directory_iterator(d), fs::directory_iterator()) == 1);
  fs::remove_all(d);
}

// A child holds a temporary and waits; each signal must remove it. The pipe
// makes the order certain: the signal is sent only once the file exists.
TEST(TempFile, SignalsRemoveLiveTemporaries) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const fs::path d = scratch("signal" + std::to_string(sig));
    const std::string out = (d / "o.h5").string();
    int ready[2];
    ASSERT_EQ(pipe(ready), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      TempFile t(out);
      std::ofstream(t.path()) << "half-written";
      const char c = 1;
      if (write(ready[1], &c, 1) != 1) _exit(3);
      pause();
      _exit(0);
    }
    char c = 0;
    ASSERT_EQ(read(ready[0], &c, 1), 1);
    const std::string tmp = out + ".tmp." + std::to_string(child);
    EXPECT_TRUE(fs::exists(tmp));
    kill(child, sig);
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "the signal's own ending was not kept";
    EXPECT_FALSE(fs::exists(tmp)) << "signal " << sig << " left " << tmp;
    close(ready[0]);
    close(ready[1]);
    fs::remove_all(d);
  }
}

TEST(TempFile, StaleTemporariesOfGoneProcessesAreRemoved) {
  const fs::path d = scratch("stale");
  const std::string out = (d / "o.h5").string();
  const pid_t gone = fork();
  if (gone == 0) _exit(0);
  ASSERT_GT(gone, 0);
  waitpid(gone, nullptr, 0);
  std::ofstream(out + ".tmp." + std::to_string(gone)) << "left by a killed writer";
  std::ofstream(out + ".tmp." + std::to_string(getppid())) << "a running process's";  // our parent runs
  std::ofstream(out + ".tmp.notapid") << "not ours";
  EXPECT_EQ(remove_stale_temps(out), 1);
  EXPECT_FALSE(fs::exists(out + ".tmp." + std::to_string(gone)));
  EXPECT_TRUE(fs::exists(out + ".tmp." + std::to_string(getppid())));
  EXPECT_TRUE(fs::exists(out + ".tmp.notapid"));
  fs::remove_all(d);
}
