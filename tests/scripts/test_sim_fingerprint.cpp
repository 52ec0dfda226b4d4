// scripts/sim_fingerprint.cmake, the key of validate's table cache: on a small
// tree laid out like mcref's, an edit to validate/, to a model sim/ does not
// include, or to the report leaves the fingerprint unchanged; an edit to sim/,
// to a models/ file sim/ includes (or the .cpp beside it) or to the build
// description changes it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::map<std::string, std::string> kTree = {
    {"sim/walk/walk.cpp", "#include \"sim/walk/walk.h\"\n#include \"models/sggx/phase.h\"\n#include <vector>\nint walk() { return 1; }\n"},
    {"sim/walk/walk.h", "#pragma once\n#include \"models/core/rng.h\"\nint walk();\n"},
    {"sim/hdf5/writer.cpp", "#include \"mcref_commit.h\"  // generated, not in the tree\nint w;\n"},
    {"models/core/rng.h", "#pragma once\n// a counter-based RNG\n"},
    {"models/sggx/phase.h", "#pragma once\ndouble phase();\n"},
    {"models/sggx/phase.cpp", "#include \"models/sggx/phase.h\"\ndouble phase() { return 0.5; }\n"},
    {"models/micrograin/smith.h", "#pragma once\ndouble smith();\n"},
    {"models/micrograin/smith.cpp", "#include \"models/micrograin/smith.h\"\ndouble smith() { return 1; }\n"},
    {"validate/suite.cpp", "#include \"sim/walk/walk.h\"\n#include \"models/micrograin/smith.h\"\n"},
    {"validate/report.cpp", "// the report\n"},
    {"scripts/plot_validation.py", "print('plots')\n"},
};

class SimFingerprint : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mcref_fingerprint_" + std::to_string(getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The fingerprint of the small tree after `edit` appends a line to one file
  // (or creates it), with the build description `build`.
  std::string fingerprint(const std::string& edit = "", const std::string& build = "gcc 12; -O2") {
    fs::remove_all(dir_);
    for (const auto& [name, text] : kTree) write(name, text);
    if (!edit.empty()) std::ofstream(dir_ / "tree" / edit, std::ios::app) << "// edited\n";
    return run(dir_ / "tree", build);
  }

  std::string run(const fs::path& src, const std::string& build) {
    const fs::path out = dir_ / "fingerprint.h";
    manifest_ = dir_ / "manifest.txt";
    const std::string cmd = std::string("'") + MCREF_CMAKE + "' -DSRC='" + src.string() + "' -DOUT='" + out.string() +
                            "' '-DBUILD=" + build + "' -DMANIFEST='" + manifest_.string() + "' -P '" + MCREF_SOURCE_DIR +
                            "/scripts/sim_fingerprint.cmake'";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(out);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    const std::string key = "MCREF_SIM_FINGERPRINT \"";
    const std::size_t at = text.find(key);
    EXPECT_NE(at, std::string::npos) << text;
    return at == std::string::npos ? "" : text.substr(at + key.size(), 16);
  }

  std::string manifest() const {
    std::ifstream in(manifest_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  void write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / "tree" / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  }

  fs::path dir_, manifest_;
};

TEST_F(SimFingerprint, EditsOutsideWhatSimReachesKeepIt) {
  const std::string base = fingerprint();
  ASSERT_EQ(base.size(), 16u);
  EXPECT_EQ(fingerprint(), base) << "not a function of the tree";
  for (const char* f : {"validate/suite.cpp", "validate/report.cpp", "models/micrograin/smith.cpp",
                        "models/micrograin/smith.h", "scripts/plot_validation.py", "validate/new_check.cpp"})
    EXPECT_EQ(fingerprint(f), base) << "an edit to " << f << " changed the fingerprint";
}

TEST_F(SimFingerprint, EditsToWhatSimComputesChangeIt) {
  const std::string base = fingerprint();
  for (const char* f : {"sim/walk/walk.cpp", "sim/walk/walk.h", "sim/hdf5/writer.cpp", "sim/new_file.cpp",
                        "models/core/rng.h", "models/sggx/phase.h", "models/sggx/phase.cpp"})
    EXPECT_NE(fingerprint(f), base) << "an edit to " << f << " left the fingerprint unchanged";
  EXPECT_NE(fingerprint("", "gcc 13; -O2"), base) << "the build description is not part of it";
}

// On mcref's own tree: the manifest holds sim/ and the models sim/ includes
// (the RNG, the SGGX phase functions, the phi sampler that the phi_conditional
// table histograms), and nothing of validate/ or of the other micrograin
// models, which only validate uses.
TEST_F(SimFingerprint, RealTreeCoversSimAndTheModelsItIncludes) {
  fs::create_directories(dir_);
  EXPECT_EQ(run(MCREF_SOURCE_DIR, "x").size(), 16u);
  const std::string m = manifest();
  for (const char* f : {"\nsim/slab/walk.cpp ", "\nmodels/core/rng.h ", "\nmodels/sggx/sggx_distribution.cpp ",
                        "\nmodels/micrograin/phi_conditional.cpp "})
    EXPECT_NE(m.find(f), std::string::npos) << f << " missing from\n" << m;
  for (const char* f : {"\nvalidate/", "\nscripts/", "\ntests/"})
    EXPECT_EQ(m.find(f), std::string::npos) << f << " in\n" << m;
  for (std::size_t at = m.find("\nmodels/micrograin/"); at != std::string::npos; at = m.find("\nmodels/micrograin/", at + 1))
    EXPECT_EQ(m.compare(at, 34, "\nmodels/micrograin/phi_conditional"), 0) << m.substr(at + 1, m.find(' ', at) - at - 1)
                                                                           << " in\n" << m;
}

}  // namespace
