// What mcref promises about data (README, "Data safety"), kept under faults
// and hostile input: an output never replaces an input, outputs are checked
// before any work, a full disk gives one line and exit 1 (no crash) and keeps
// the old file, temporaries never outlive their writer, and values that do
// not fit their type are refused.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/validate/app/cli_fixture.h"

namespace fs = std::filesystem;
using namespace mcref_test;

namespace {

// A small slab experiment (writes a few hundred kB of tables with 2 batches).
std::string slab_experiment() {
  return "[geometry]\nkind = \"slab\"\n[[geometry.layer]]\nphase = \"isotropic\"\noptical_thickness = 1.0\nalbedo = 0.5\n"
         "[run]\nseed = 1\nbatches = 2\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0, 30, 60]\n"
         "theta_o_bins = 30\nphi_bins = 36\nsamples = 200\n";
}

// A tmpfs of `kib` KiB mounted on `dir` (root only); false if it cannot be mounted.
bool mount_tiny_tmpfs(const fs::path& dir, int kib) {
  fs::create_directories(dir);
  const std::string opts = "size=" + std::to_string(kib) + "k";
  return mount("tmpfs", dir.c_str(), "tmpfs", 0, opts.c_str()) == 0;
}

}  // namespace

TEST_F(Cli, OutputNamingAnInputIsRefused) {
  const std::string exp = write("x.toml", experiment());
  const std::string before = slurp(exp);
  for (const std::string& out : {exp, path("./x.toml"), path("sub/../x.toml")}) {
    fs::create_directories(path("sub"));
    expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet"), {"-o", "is the input"});
    EXPECT_EQ(slurp(exp), before) << "the experiment was changed through " << out;
  }
  fs::create_symlink(exp, path("link.toml"));
  expect_one_line_error(mcref("simulate " + quote(path("link.toml")) + " -o " + quote(exp) + " --quiet"),
                        {"is the input"});
  expect_one_line_error(mcref("export-vdb " + quote(exp) + " -o " + quote(exp)), {"is the input"});
  EXPECT_EQ(slurp(exp), before);
  // merge: the output may not be one of the shards.
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("t.h5")) + " --quiet").exit_code, 0);
  const std::string shard = slurp(path("t.h5"));
  expect_one_line_error(mcref("merge " + quote(path("t.h5")) + " -o " + quote(path("t.h5")) + " --quiet"),
                        {"is the input"});
  EXPECT_EQ(slurp(path("t.h5")), shard);
}

// geometry.density_vdb is an input too: simulate, export-vdb and dataset refuse
// an output naming it, and leave it as it was.
TEST_F(Cli, OutputNamingTheDensityVdbIsRefused) {
  const std::string base = "[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\n";
  const std::string layer = "[[geometry.layer]]\nphase = \"isotropic\"\nalbedo = 0.5\n";
  const std::string rest = "[run]\nseed = 1\nbatches = 2\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  const std::string vdb = path("d.vdb");
  ASSERT_EQ(mcref("export-vdb " + quote(write("e.toml", base + layer + "density = 2.0\n" + rest)) + " -o " + quote(vdb) + " --quiet")
                .exit_code,
            0);
  const std::string before = slurp(vdb);
  const std::string exp = write("x.toml", base + "density_vdb = \"d.vdb\"\n" + layer + rest);
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(vdb) + " --quiet"), {"-o", "is the input"});
  expect_one_line_error(mcref("export-vdb " + quote(exp) + " -o " + quote(path("./d.vdb")) + " --quiet"), {"is the input"});
  write("ds.toml", "[dataset]\nexperiment = \"x.toml\"\n[[parameter]]\nkey = \"geometry.layer.0.albedo\"\nvalues = [0.2]\n");
  expect_one_line_error(mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(vdb) + " --quiet"), {"is the input"});
  EXPECT_EQ(slurp(vdb), before);
  EXPECT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("t.h5")) + " --quiet").exit_code, 0);
}

TEST_F(Cli, OutputLocationsAreCheckedBeforeAnyWork) {
  const std::string exp = write("x.toml", experiment());
  const std::string missing = path("missing/dir/x.h5");
  // The same rule for every verb: mcref creates no directory for an output file.
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(missing) + " --quiet"), {missing, "does not exist"});
  expect_one_line_error(mcref("export-vdb " + quote(write("s.toml", slab_experiment())) + " -o " + quote(missing)),
                        {missing, "does not exist"});
  EXPECT_FALSE(fs::exists(path("missing")));
  // An existing directory as an output file, and a file as validate's output directory.
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(dir_.string()) + " --quiet"), {"is a directory"});
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"c\"\nexperiment = \"x.toml\"\n");
  write("afile", "keep");
  expect_one_line_error(mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("afile")) + " --quiet"),
                        {"afile", "not a directory"});
  EXPECT_EQ(slurp(path("afile")), "keep");
  for (const std::string& s : stray({"x.toml", "s.toml", "suite.toml", "afile"})) ADD_FAILURE() << "left behind: " << s;
}

// A read-only output directory, for every verb that writes: a read-only tmpfs
// as root (permissions do not stop root), a directory without write
// permission otherwise.
TEST_F(Cli, ReadOnlyOutputDirectoriesAreRefusedBeforeAnyWork) {
  const fs::path ro = dir_ / "ro";
  fs::create_directories(ro);
  const bool mounted = geteuid() == 0 && mount("tmpfs", ro.c_str(), "tmpfs", MS_RDONLY, "size=64k") == 0;
  if (geteuid() == 0 && !mounted) GTEST_SKIP() << "cannot mount a read-only tmpfs here";
  if (!mounted) fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
  write("x.toml", experiment());
  write("s.toml", slab_experiment());
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"c\"\nexperiment = \"x.toml\"\n");
  write("ds.toml", "[dataset]\nexperiment = \"x.toml\"\n[[parameter]]\nkey = \"geometry.tau0\"\nvalues = [0.3, 0.6]\n");
  ASSERT_EQ(mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("d.h5")) + " --quiet").exit_code, 0);
  for (const std::string& verb : {"simulate " + quote(path("x.toml")) + " -o " + quote((ro / "o.h5").string()),
                                  "export-vdb " + quote(path("s.toml")) + " -o " + quote((ro / "g.vdb").string()),
                                  "validate " + quote(path("suite.toml")) + " -o " + quote((ro / "v").string()),
                                  "dataset " + quote(path("ds.toml")) + " -o " + quote((ro / "d.h5").string()),
                                  "merge " + quote(path("d.h5")) + " -o " + quote((ro / "m.h5").string())}) {
    const Result r = mcref(verb);
    EXPECT_EQ(r.exit_code, 2) << verb << ": " << r.err;
    expect_one_line_error(r, {(ro).string(), "not writable"});
  }
  if (mounted) umount(ro.c_str());
  else fs::permissions(ro, fs::perms::owner_all);
}

TEST_F(Cli, BadValuesAreRefusedNotClamped) {
  // Booleans are booleans: 1 is not true.
  expect_rejected(slab_experiment(), {"geometry.delta_transmission", "true or false"}, "--set geometry.delta_transmission=1");
  const std::string exp = write("x.toml", experiment());
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(path("o.h5")) + " --seed 99999999999999999999"),
                        {"--seed", "99999999999999999999"});
  // A directory given as the experiment.
  expect_one_line_error(mcref("simulate " + quote(dir_.string()) + " -o " + quote(path("o.h5"))), {"is a directory"});
  // --voxel-size far too small: the count is reported as a number, never a wrapped integer.
  const Result r = mcref("export-vdb " + quote(exp) + " -o " + quote(path("g.vdb")) + " --voxel-size 1e-6");
  expect_one_line_error(r, {"--voxel-size", "voxels"});
  EXPECT_EQ(r.err.find("-9223372036854775808"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("o.h5")));
}

TEST_F(Cli, MeasureNamesThatCouldCollideAreRefusedBeforeWork) {
  const std::string tau = "quantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 2000\n";
  const std::string g1 = "quantity = \"g1\"\ntheta_i_deg = [30]\nsamples = 2000\n";
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "", g1 + "\n[[measure]]\nname = \"g1_conditional\"\n" + tau),
                  {"bad.toml", "measure.1.name", "g1_conditional"});
  for (const std::string& name : {"a/b", "a.b", ""})
    expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "", "name = \"" + name + "\"\n" + tau),
                    {"bad.toml", "measure.0.name"});
}

TEST_F(Cli, StaleTemporariesOfDeadWritersAreRemoved) {
  const std::string exp = write("x.toml", experiment());
  // A pid that no longer runs: a child that has exited and been reaped.
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  ASSERT_GT(dead, 0);
  waitpid(dead, nullptr, 0);
  write("o.h5.tmp." + std::to_string(dead), "half-written");
  write("o.h5.tmp." + std::to_string(getpid()), "a live writer's");  // this test process runs
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("o.h5")) + " --quiet").exit_code, 0);
  EXPECT_FALSE(fs::exists(path("o.h5.tmp." + std::to_string(dead))));
  EXPECT_TRUE(fs::exists(path("o.h5.tmp." + std::to_string(getpid()))));
}

TEST_F(Cli, FullDiskGivesOneLineAndKeepsTheOldFile) {
  const fs::path disk = dir_ / "disk";
  if (geteuid() != 0 || !mount_tiny_tmpfs(disk, 96)) GTEST_SKIP() << "cannot mount a small tmpfs here (needs root)";
  const std::string exp = write("s.toml", slab_experiment());
  const std::string small = write("small.toml", experiment());
  const std::string out = (disk / "t.h5").string();
  ASSERT_EQ(mcref("simulate " + quote(small) + " -o " + quote(out) + " --quiet").exit_code, 0);
  const std::string good = slurp(out);
  const Result r = mcref("simulate " + quote(exp) + " -o " + quote(out) + " --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.err;  // not a crash (139), not bad input (2)
  expect_one_line_error(r, {out});
  EXPECT_EQ(slurp(out), good) << "the old file was replaced";
  const Result v = mcref("export-vdb " + quote(exp) + " -o " + quote((disk / "g.vdb").string()) +
                         " --set geometry.lateral_voxels=128 --set geometry.depth_voxels=128");
  EXPECT_EQ(v.exit_code, 1) << v.err;
  expect_one_line_error(v, {"g.vdb"});
  // A dataset's part, merge's output and validate's tables on the full disk.
  write("ds.toml", "[dataset]\nexperiment = \"s.toml\"\n[[parameter]]\nkey = \"geometry.layer.0.albedo\"\nvalues = [0.2, 0.4]\n");
  const Result d = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote((disk / "d.h5").string()) + " --quiet");
  EXPECT_EQ(d.exit_code, 1) << d.err;
  expect_one_line_error(d, {"d.h5.parts/entry-0.h5", "writing failed"});
  for (const char* shard : {"0/2", "1/2"})
    ASSERT_EQ(mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path(std::string("s") + shard[0] + ".h5")) +
                    " --quiet --shard " + shard).exit_code, 0);
  const Result m = mcref("merge " + quote(path("s0.h5")) + " " + quote(path("s1.h5")) + " -o " + quote((disk / "m.h5").string()));
  EXPECT_EQ(m.exit_code, 1) << m.err;
  expect_one_line_error(m, {"m.h5", "writing failed"});
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"a\"\nexperiment = \"s.toml\"\n");
  const Result s = mcref("validate " + quote(path("suite.toml")) + " -o " + quote((disk / "v").string()) + " --quiet");
  EXPECT_EQ(s.exit_code, 1) << s.err;
  expect_one_line_error(s, {"a.h5"});
  for (const auto& e : fs::recursive_directory_iterator(disk))
    EXPECT_TRUE(e.path().filename() == "t.h5" || fs::is_directory(e.path())) << "left on the full disk: " << e.path();
  umount(disk.c_str());
}

TEST_F(Cli, CostCliffsAreRefusedUpFront) {
  // Micrograin rays so grazing that they would wrap the tile past the bound.
  expect_rejected(experiment("tau0 = 0.5\nbeta = 0.8\n", "",
                             "quantity = \"tau_plus\"\ntheta_i_deg = [89.999999]\nsamples = 2000\n"),
                  {"bad.toml", "measure.0.theta_i_deg", "too grazing"});
  // A slab whose density gives an optical thickness past the walk's bound.
  std::string dense = slab_experiment();
  dense.replace(dense.find("optical_thickness = 1.0"), 23, "thickness = 1e3\ndensity = 1e4");
  expect_rejected(dense, {"bad.toml", "density", "1e6"});
}

// A sealed table file edited through HDF5 is refused by its seal. Without a
// seal (files from before seals: the user block cut off, which HDF5 allows),
// the table reader's own checks still refuse missing or altered values.
TEST_F(Cli, EditedOrDamagedTablesAreRefused) {
  const std::string exp = write("x.toml", experiment());
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("t.h5")) + " --quiet").exit_code, 0);
  const std::string sealed = slurp(path("t.h5"));
  ASSERT_EQ(sealed.compare(0, 13, "mcref-seal 1 "), 0) << "no seal at the start of the file";
  std::ofstream(path("legacy.h5"), std::ios::binary) << sealed.substr(512);
  const Result good = mcref("info " + quote(path("t.h5")));
  const Result legacy = mcref("info " + quote(path("legacy.h5")));
  ASSERT_EQ(good.exit_code, 0) << good.err;
  ASSERT_EQ(legacy.exit_code, 0) << legacy.err;
  const auto after_name = [](const std::string& out) { return out.substr(out.find('\n')); };
  EXPECT_EQ(after_name(legacy.out), after_name(good.out)) << "an unsealed copy reads differently";
  const auto set_first_value = [](const std::string& file, double v) {
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0) << file;
    const hid_t d = H5Dopen2(f, "tau_plus/value", H5P_DEFAULT);
    const hid_t space = H5Dget_space(d);
    std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Sclose(space);
    const bool read = H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0;
    values.at(0) = v;
    const bool written = read && H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0;
    H5Dclose(d);
    H5Fclose(f);
    ASSERT_TRUE(written) << file;
  };
  fs::copy_file(path("t.h5"), path("edited.h5"));
  set_first_value(path("edited.h5"), 0.123456);
  expect_one_line_error(mcref("info " + quote(path("edited.h5"))), {"edited.h5", "no longer match the seal"});
  fs::copy_file(path("legacy.h5"), path("changed.h5"));
  set_first_value(path("changed.h5"), 0.123456);
  expect_one_line_error(mcref("info " + quote(path("changed.h5"))), {"changed.h5", "does not match"});
  fs::copy_file(path("legacy.h5"), path("novalue.h5"));
  {
    const hid_t f = H5Fopen(path("novalue.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_GE(H5Ldelete(f, "tau_plus/value", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  expect_one_line_error(mcref("info " + quote(path("novalue.h5"))), {"novalue.h5", "no value"});
}

// SGGX alpha at the ends of its range on a tilted fibre layer (the worst
// conditioned S): the lower end runs, below it is refused before any work.
TEST_F(Cli, SggxAlphaRangeEndsRunOrAreRefused) {
  std::string fiber = slab_experiment();
  fiber.replace(fiber.find("phase = \"isotropic\""), 19, "phase = \"sggx_fiber\"\norientation = [1, 1, 1]\nalpha = 1e-4");
  for (const char* alpha : {"1e-4", "1e3"}) {
    const Result r = mcref("simulate " + quote(write("f.toml", fiber)) + " -o " + quote(path("f.h5")) +
                           " --quiet --set geometry.layer.0.alpha=" + alpha);
    EXPECT_EQ(r.exit_code, 0) << "alpha " << alpha << ": " << r.err;
    fs::remove(path("f.h5"));
  }
  fs::remove(path("f.toml"));
  expect_rejected(fiber, {"bad.toml", "alpha", "1e-05"}, "--set geometry.layer.0.alpha=1e-5");
}

// A ratio estimate whose denominator was 0 in a batch (tau0 = 1e-9: no grain
// to sample a normal from) is an empty cell: NaN, with a NaN stderr (0 would
// claim an exact value), and `info` counts such cells.
TEST_F(Cli, EmptyCellsAreNaNWithoutAnErrorBar) {
  const std::string exp = write("e.toml", experiment("tau0 = 1e-9\nbeta = 0.8\n", "", "quantity = \"ndf\"\nsamples = 1\n"));
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("e.h5")) + " --quiet").exit_code, 0);
  const Result r = mcref("info " + quote(path("e.h5")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("empty cells="), std::string::npos) << r.out;
  const hid_t f = H5Fopen(path("e.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char* name : {"ndf/value", "ndf/stderr"}) {
    const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
    const hid_t space = H5Dget_space(d);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Sclose(space);
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
    H5Dclose(d);
    for (double x : v) EXPECT_TRUE(std::isnan(x)) << name << " holds " << x;
  }
  EXPECT_GT(H5Aexists_by_name(f, "ndf", "empty_cells", H5P_DEFAULT), 0);
  H5Fclose(f);
}

// Dilute sphere packings whose free flights would wrap the tile more than 100
// times are refused before any work, pointing to the volumetric limit.
TEST_F(Cli, DiluteSpherePackingsAreRefusedUpFront) {
  const std::string spheres =
      "[geometry]\nkind = \"spheres\"\nalbedo = 0.5\nvolume_fraction = 1e-6\n[run]\nseed = 1\nbatches = 2\n"
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0]\ntheta_o_bins = 4\nphi_bins = 4\nsamples = 100\n";
  expect_rejected(spheres, {"bad.toml", "volume_fraction", "volumetric"});
  std::string volumetric = spheres;
  volumetric.replace(volumetric.find("albedo"), 0, "placement = \"volumetric\"\n");
  EXPECT_EQ(mcref("simulate " + quote(write("v.toml", volumetric)) + " -o " + quote(path("v.h5")) + " --quiet").exit_code, 0);
}
