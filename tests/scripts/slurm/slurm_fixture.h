#pragma once
// The SLURM recipes of scripts/slurm/ run locally, as SLURM would run them:
// the same scripts with the variables SLURM sets (array task id and count,
// cpus per task), against a single-process run of the same dataset.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "tests/sim/parallel/mpi_cli.h"

namespace mcref_test {

namespace fs = std::filesystem;

inline const char* kSlurmBase = R"(
[geometry]
kind = "slab"

[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.8

[run]
seed = 1
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [20, 60]
theta_o_bins = 3
phi_bins = 2
samples = 300
)";

inline const char* kSlurmDataset = R"(
[dataset]
experiment = "base.toml"
entries = 7
seed = 5

[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.1, 10.0]
distribution = "log_uniform"
)";

class SlurmRecipe : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mcref_test_slurm_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml") << kSlurmBase;
    std::ofstream(dir_ / "ds.toml") << kSlurmDataset;
    std::string err;
    ASSERT_EQ(shell(dir_, mcref("dataset ds.toml -o one.h5 --quiet"), &err), 0) << err;
  }
  void TearDown() override { fs::remove_all(dir_); }
  // `bash scripts/slurm/<script> args` with `env` set, as the batch system would run it.
  int run_script(const std::string& env, const std::string& script, const std::string& args, std::string* err) const {
    return shell(dir_, env + " MCREF='" + std::string(MCREF_BINARY) + "' bash '" + std::string(MCREF_SOURCE_DIR) +
                           "/scripts/slurm/" + script + "' " + args, err);
  }
  // README.md shows `line` (the recipe is documented as it is tested).
  static bool readme_shows(const std::string& line) {
    return slurp(fs::path(MCREF_SOURCE_DIR) / "README.md").find(line) != std::string::npos;
  }
  fs::path dir_;
};

}  // namespace mcref_test
