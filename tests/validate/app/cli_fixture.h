#pragma once
// The harness of the command-line tests (MCREF_BINARY): runs mcref in a
// scratch directory of its own and checks the one-line error contract.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace mcref_test {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Lines of a text, without the trailing newline.
inline std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == '\n') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mcref_test_cli_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs mcref with the given (already quoted) arguments, capturing stdout
  // and stderr in files of the scratch directory.
  Result mcref(const std::string& args) const { return shell(quote(MCREF_BINARY) + " " + args); }

  // Runs a shell command line the same way.
  Result shell(const std::string& command) const {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const std::string cmd = command + " > " + quote(out) + " 2> " + quote(err);
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

  // Entries of the scratch directory other than the given ones.
  std::vector<std::string> stray(const std::vector<std::string>& expected) const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      bool known = false;
      for (const std::string& x : expected) known = known || x == n;
      if (!known) out.push_back(n);
    }
    return out;
  }

  // A bad `mcref simulate` run: non-zero exit, one stderr line holding every
  // `expected` piece, no output file and no temporary left.
  void expect_rejected(const std::string& toml, const std::vector<std::string>& expected,
                       const std::string& extra_args = "") {
    const std::string exp = write("bad.toml", toml);
    const std::string out = path("out.h5");
    const Result r = mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet " + extra_args);
    expect_one_line_error(r, expected);
    EXPECT_FALSE(fs::exists(out)) << "an output file was written";
    for (const std::string& s : stray({"bad.toml"})) ADD_FAILURE() << "left behind: " << s;
  }

  static void expect_one_line_error(const Result& r, const std::vector<std::string>& expected) {
    EXPECT_NE(r.exit_code, 0) << "stderr: " << r.err;
    const std::vector<std::string> ls = lines(r.err);
    ASSERT_EQ(ls.size(), 1u) << "stderr is not one line:\n" << r.err;
    for (const std::string& piece : expected)
      EXPECT_NE(ls[0].find(piece), std::string::npos) << "'" << piece << "' missing from: " << ls[0];
  }

  fs::path dir_;
};

// A small valid experiment; `geometry`, `run` and `measure` replace the sections.
inline std::string experiment(const std::string& geometry = "tau0 = 0.5\nbeta = 0.8\n", const std::string& run = "",
                       const std::string& measure = "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 2000\n") {
  return "[geometry]\nkind = \"micrograin\"\ntile = 20\n" + geometry + "\n[run]\nseed = 3\nbatches = 2\n" + run +
         "\n[[measure]]\n" + measure;
}

}  // namespace mcref_test
