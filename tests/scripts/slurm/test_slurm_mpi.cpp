// The MPI recipe (scripts/slurm/dataset_mpi.sbatch) with mpirun standing in
// for srun: the same script, the bytes of a single-process run.
#include "tests/scripts/slurm/slurm_fixture.h"

using namespace mcref_test;

TEST_F(SlurmRecipe, MpiJobGivesTheBytesOfOneProcess) {
  std::string err;
  // The script expands MCREF_LAUNCH unquoted, as a user's "srun --mpi=pmix".
  const std::string launch = std::string("MCREF_LAUNCH=\"") + MCREF_MPIEXEC +
                             " -q --allow-run-as-root --oversubscribe -np 2\" SLURM_CPUS_PER_TASK=1";
  ASSERT_EQ(run_script(launch, "dataset_mpi.sbatch", "ds.toml mpi.h5", &err), 0) << err;
  EXPECT_EQ(shell(dir_, "cmp one.h5 mpi.h5", nullptr), 0);
  // Submitted again (after a timeout, say): up to date, the same file.
  ASSERT_EQ(run_script(launch, "dataset_mpi.sbatch", "ds.toml mpi.h5", &err), 0) << err;
  EXPECT_NE(err.find("up to date"), std::string::npos) << err;
  EXPECT_TRUE(readme_shows("sbatch scripts/slurm/dataset_mpi.sbatch DATASET.toml DATA.h5"));
}
