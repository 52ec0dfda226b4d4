// Damaged files (issue #20, class 5): a fixed-seed corpus of corrupted copies
// of a table file and of a dataset file, each read by mcref under a time
// limit. Every read must end in a one-line error naming the file, or (when the
// damage left the bytes as they were) in the original result: never a crash,
// a hang, or different contents.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>

#include "tests/validate/app/cli_fixture.h"

namespace fs = std::filesystem;
using namespace mcref_test;

namespace {

constexpr std::uint64_t kSeed = 20;      // the corpus
constexpr int kCopies = 120;             // per file kind
constexpr const char* kLimit = "timeout -s KILL 20 ";  // a hang fails as exit 137

// One corruption of `bytes`: bit flips, a run of random bytes, a zeroed run,
// or a truncation, at a uniformly chosen place.
std::string corrupt(std::string bytes, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  switch (rng() % 4) {
    case 0:
      for (int k = 1 + static_cast<int>(pick(8)); k > 0; --k) bytes[pick(bytes.size())] ^= static_cast<char>(1 << pick(8));
      break;
    case 1: {
      const std::size_t at = pick(bytes.size()), n = std::min<std::size_t>(1 + pick(64), bytes.size() - at);
      for (std::size_t i = 0; i < n; ++i) bytes[at + i] = static_cast<char>(rng());
      break;
    }
    case 2: {
      const std::size_t at = pick(bytes.size()), n = std::min<std::size_t>(1 + pick(4096), bytes.size() - at);
      std::fill_n(bytes.begin() + static_cast<std::ptrdiff_t>(at), n, '\0');
      break;
    }
    default:
      bytes.resize(pick(bytes.size()));
  }
  return bytes;
}

}  // namespace

class CliFuzz : public Cli {
 protected:
  // Runs `mcref ARGS` with ARGS = args(file) on kCopies corrupted copies of
  // `good`; `result(r)` is what must equal the good file's when a run succeeds.
  template <class Args, class ResultOf>
  void run_corpus(const std::string& good, Args args, ResultOf result) {
    const std::string original = slurp(good);
    const Result reference = mcref(args(good));
    ASSERT_EQ(reference.exit_code, 0) << reference.err;
    const std::string expected = result(reference);
    std::mt19937_64 rng(kSeed);
    int refused = 0, unchanged = 0;
    for (int k = 0; k < kCopies; ++k) {
      const std::string bytes = corrupt(original, rng);
      const std::string file = path("c" + std::to_string(k) + ".h5");
      std::ofstream(file, std::ios::binary) << bytes;
      const Result r = shell(std::string(kLimit) + quote(MCREF_BINARY) + " " + args(file));
      SCOPED_TRACE("copy " + std::to_string(k) + " (seed " + std::to_string(kSeed) + ")");
      ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 2)
          << "exit " << r.exit_code << " (137: a hang, killed; 139: a crash); stderr: " << r.err;
      if (r.exit_code == 0) {
        EXPECT_EQ(bytes, original) << "a damaged file was read without error";
        EXPECT_EQ(result(r), expected);
        ++unchanged;
      } else {
        const std::vector<std::string> ls = lines(r.err);
        ASSERT_EQ(ls.size(), 1u) << r.err;
        EXPECT_NE(ls[0].find(file), std::string::npos) << ls[0];
        ++refused;
      }
      fs::remove(file);
    }
    std::printf("corpus of %d copies (seed %llu): %d refused, %d unchanged and read correctly\n", kCopies,
                static_cast<unsigned long long>(kSeed), refused, unchanged);
    EXPECT_GT(refused, kCopies / 2) << "the corpus hardly damages anything: the test would prove little";
  }
};

TEST_F(CliFuzz, DamagedTableFilesGiveOneLineErrors) {
  const std::string exp = write("x.toml", experiment());
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("t.h5")) + " --quiet").exit_code, 0);
  // info's first line names the file; the rest is the contents.
  run_corpus(
      path("t.h5"), [](const std::string& f) { return "info " + quote(f); },
      [](const Result& r) { return r.out.substr(std::min(r.out.size(), r.out.find('\n'))); });
}

TEST_F(CliFuzz, DamagedDatasetFilesGiveOneLineErrors) {
  write("base.toml", experiment());
  const std::string ds = write("d.toml",
                               "[dataset]\nexperiment = \"base.toml\"\nentries = 3\nseed = 7\n"
                               "[[parameter]]\nkey = \"geometry.tau0\"\nrange = [0.2, 0.8]\n");
  ASSERT_EQ(mcref("dataset " + quote(ds) + " -o " + quote(path("d.h5")) + " --quiet").exit_code, 0);
  // merge reads every entry of its one input and writes them again.
  const std::string out = path("merged.h5");
  run_corpus(
      path("d.h5"), [&](const std::string& f) { return "merge " + quote(f) + " -o " + quote(out) + " --quiet"; },
      [&](const Result&) {
        const std::string bytes = slurp(out);
        fs::remove(out);
        return bytes;
      });
}
