// sim/files/output_path.h: an output that resolves to an input is refused
// (same path, "./", "..", symbolic and hard links), as are directories given
// as files and missing parent directories.
#include <gtest/gtest.h>
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
