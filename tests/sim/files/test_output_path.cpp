// sim/files/output_path.h: an output that resolves to an input is refused
// (same path, "./", "..", symbolic and hard links), as are directories given
// as files, missing parent directories, FIFOs, names too long for their
// temporary, and inputs inside a directory the run writes into.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sim/experiment/config_error.h"
#include "sim/files/output_path.h"

namespace fs = std::filesystem;
using namespace mcref;

TEST(OutputPath, SameFileSeesThroughLinksAndDots) {
  const fs::path d = fs::temp_directory_path() / ("mcref_test_output_path_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "sub");
  const std::string in = (d / "in.toml").string();
  std::ofstream(in) << "x";
  fs::create_symlink(in, d / "sym.toml");
  fs::create_hard_link(in, d / "hard.toml");
  for (const fs::path& p : {fs::path(in), d / "." / "in.toml", d / "sub" / ".." / "in.toml", d / "sym.toml", d / "hard.toml"}) {
    EXPECT_TRUE(same_file(p.string(), in)) << p;
    EXPECT_THROW(check_output_file(p.string(), {in}), ConfigError) << p;
  }
  EXPECT_FALSE(same_file((d / "out.h5").string(), in));
  EXPECT_NO_THROW(check_output_file((d / "out.h5").string(), {in}));
  EXPECT_THROW(check_output_file((d / "sub").string(), {in}), ConfigError);
  EXPECT_THROW(check_output_file((d / "missing" / "out.h5").string(), {in}), ConfigError);
  EXPECT_THROW(check_output_directory(in, {}), ConfigError);  // a file, not a directory
  EXPECT_NO_THROW(check_output_directory((d / "new").string(), {in}));
  EXPECT_THROW(check_output_directory((d / "missing" / "new").string(), {in}), ConfigError);
  fs::remove_all(d);
}

// check_inputs_outside: an input inside the directory (named there, through
// "..", or a link from outside to a file there) is refused; a sibling whose
// name only starts like the directory's, and the directory's own parent, are not.
TEST(OutputPath, InputsInsideAWrittenDirectoryAreRefused) {
  const fs::path d = fs::temp_directory_path() / ("mcref_test_output_inside_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "out.h5.parts" / "sub");
  const std::string part = (d / "out.h5.parts" / "entry-0.h5").string();
  std::ofstream(part) << "x";
  std::ofstream(d / "out.h5.parts2") << "x";
  fs::create_symlink(part, d / "link.toml");
  const std::string dir = (d / "out.h5.parts").string();
  for (const fs::path& p : {fs::path(part), d / "out.h5.parts" / "sub" / ".." / "entry-0.h5", d / "link.toml",
                            d / "out.h5.parts" / "missing.toml"})
    EXPECT_THROW(check_inputs_outside(dir, {p.string()}, "mcref dataset -o out.h5"), ConfigError) << p;
  for (const fs::path& p : {d / "out.h5.parts2", d / "x.toml", d / "out.h5.parts"})
    EXPECT_NO_THROW(check_inputs_outside(dir, {p.string()}, "mcref dataset -o out.h5")) << p;
  fs::remove_all(d);
}

// An input named as the output's temporary (<output>.tmp.<pid>), or linking to
// such a file, is refused: TempFile removes such a file once no process has
// that pid, taking it for what a killed run left (it removed the input before).
TEST(OutputPath, InputsNamedAsTheOutputsTemporaryAreRefused) {
  const fs::path d = fs::temp_directory_path() / ("mcref_test_output_temp_name_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "sub");
  const fs::path temp = d / "out.h5.tmp.4194305";  // above pid_max's default: no such process
  std::ofstream(temp) << "x";
  fs::create_symlink(temp, d / "in.toml");
  std::ofstream(d / "out.h5.tmp.x1") << "x";
  const std::string out = (d / "out.h5").string();
  for (const fs::path& in : {temp, d / "in.toml", d / "sub" / ".." / "out.h5.tmp.4194305"})
    EXPECT_THROW(check_output_file(out, {in.string()}), ConfigError) << in;
  for (const fs::path& in : {d / "out.h5.tmp.x1", d / "sub" / "out.h5.tmp.4194305", d / "out.h5.tmp"})
    EXPECT_NO_THROW(check_output_file(out, {in.string()})) << in;
  EXPECT_TRUE(fs::exists(temp));
  fs::remove_all(d);
}

// An existing output must be a regular file (or a link, which is replaced):
// a FIFO is refused; so is a name whose temporary <name>.tmp.<pid> is too long.
TEST(OutputPath, OnlyRegularFilesAndLinksMayBeReplaced) {
  const fs::path d = fs::temp_directory_path() / ("mcref_test_output_special_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  ASSERT_EQ(mkfifo((d / "fifo").c_str(), 0644), 0);
  std::ofstream(d / "file") << "x";
  fs::create_symlink(d / "fifo", d / "link");
  EXPECT_THROW(check_output_file((d / "fifo").string(), {}), ConfigError);
  EXPECT_THROW(check_replaceable_file((d / "fifo").string(), {}), ConfigError);
  EXPECT_NO_THROW(check_output_file((d / "file").string(), {}));
  EXPECT_NO_THROW(check_output_file((d / "link").string(), {}));
  const long max = pathconf(d.c_str(), _PC_NAME_MAX);
  if (max > 0 && max < 1000) {
    EXPECT_NO_THROW(check_output_file((d / std::string(static_cast<std::size_t>(max) - 16, 'n')).string(), {}));
    EXPECT_THROW(check_output_file((d / std::string(static_cast<std::size_t>(max) - 3, 'n')).string(), {}), ConfigError);
  }
  fs::remove_all(d);
}
