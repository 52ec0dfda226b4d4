// The job-array recipe (scripts/slurm/dataset_array.sbatch, then
// dataset_merge.sbatch): each task writes its shard with --shard
// $SLURM_ARRAY_TASK_ID/N, the merge job combines them into the bytes of a
// single-process run and removes the shards.
#include "tests/scripts/slurm/slurm_fixture.h"

using namespace mcref_test;

TEST_F(SlurmRecipe, ArrayTasksThenMergeGiveTheBytesOfOneProcess) {
  const int tasks = 3;
  std::string err;
  for (int k = 0; k < tasks; ++k)
    ASSERT_EQ(run_script("SLURM_ARRAY_TASK_ID=" + std::to_string(k) + " SLURM_ARRAY_TASK_COUNT=" + std::to_string(tasks) +
                             " SLURM_CPUS_PER_TASK=1",
                         "dataset_array.sbatch", "ds.toml data 3", &err),
              0)
        << err;
  for (int k = 0; k < tasks; ++k) EXPECT_TRUE(fs::exists(dir_ / ("data.shard" + std::to_string(k) + ".h5")));
  ASSERT_EQ(run_script("", "dataset_merge.sbatch", "data 3 merged.h5", &err), 0) << err;
  EXPECT_EQ(shell(dir_, "cmp one.h5 merged.h5", nullptr), 0);
  for (int k = 0; k < tasks; ++k) EXPECT_FALSE(fs::exists(dir_ / ("data.shard" + std::to_string(k) + ".h5")));
  EXPECT_TRUE(readme_shows("jid=$(sbatch --parsable --array=0-15 scripts/slurm/dataset_array.sbatch DATASET.toml DATA 16)"));
  EXPECT_TRUE(readme_shows("sbatch --dependency=afterok:$jid scripts/slurm/dataset_merge.sbatch DATA 16 DATA.h5"));
}

TEST_F(SlurmRecipe, MergeOfMissingShardFailsAndKeepsTheShards) {
  std::string err;
  ASSERT_EQ(run_script("SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=2", "dataset_array.sbatch", "ds.toml data 2", &err), 0) << err;
  EXPECT_NE(run_script("", "dataset_merge.sbatch", "data 2 merged.h5", &err), 0);
  EXPECT_FALSE(fs::exists(dir_ / "merged.h5"));
  EXPECT_TRUE(fs::exists(dir_ / "data.shard0.h5"));
}

// A task resubmitted alone (sbatch --array=1) sees SLURM_ARRAY_TASK_COUNT=1; it
// still writes shard 1 of 3 (taking the count from there, it wrote the whole
// dataset into data.shard1.h5, and the merge failed on overlapping entries).
TEST_F(SlurmRecipe, ATaskResubmittedAloneWritesItsOwnShard) {
  std::string err;
  for (int k : {0, 2})
    ASSERT_EQ(run_script("SLURM_ARRAY_TASK_ID=" + std::to_string(k) + " SLURM_ARRAY_TASK_COUNT=3 SLURM_CPUS_PER_TASK=1",
                         "dataset_array.sbatch", "ds.toml data 3", &err),
              0)
        << err;
  ASSERT_EQ(run_script("SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=1 SLURM_CPUS_PER_TASK=1", "dataset_array.sbatch",
                       "ds.toml data 3", &err),
            0)
      << err;
  ASSERT_EQ(run_script("", "dataset_merge.sbatch", "data 3 merged.h5", &err), 0) << err;
  EXPECT_EQ(shell(dir_, "cmp one.h5 merged.h5", nullptr), 0);
}
