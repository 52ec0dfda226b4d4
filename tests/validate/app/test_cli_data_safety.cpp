// What mcref promises about data (README, "Data safety"), kept under faults
// and hostile input: an output never replaces an input, outputs are checked
// before any work, a full disk gives one line and exit 3 (no crash) and keeps
// the old file, temporaries never outlive their writer, and values that do
// not fit their type are refused.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/hdf5/h5_util.h"
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

// An input named as the output's temporary, <output>.tmp.<pid> with no such
// process, was removed as a stale temporary before the run (exit 0, input gone).
TEST_F(Cli, AnInputNamedAsTheOutputsTemporaryIsRefused) {
  const std::string exp = write("t.h5.tmp.4194305", experiment());  // above pid_max's default
  expect_one_line_error(mcref("simulate " + quote(exp) + " -o " + quote(path("t.h5")) + " --quiet"),
                        {"-o", "is named as this output's temporary"});
  EXPECT_EQ(slurp(exp), experiment());
  EXPECT_FALSE(fs::exists(path("t.h5")));
}

// A second process given the output of a running dataset is refused at once
// (it holds a lock on OUTPUT.parts/; here the test holds it). Before, two
// shard runs given one -o both exited 0: the last renamed its OUTPUT over the
// other's, and each removed the parts it found, so one shard was lost.
TEST_F(Cli, ASecondDatasetProcessOnOneOutputIsRefused) {
  write("x.toml", experiment());
  write("ds.toml", "[dataset]\nexperiment = \"x.toml\"\n[[parameter]]\nkey = \"geometry.tau0\"\nvalues = [0.3, 0.6]\n");
  fs::create_directories(path("d.h5.parts"));
  const int fd = open(path("d.h5.parts").c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(flock(fd, LOCK_EX | LOCK_NB), 0);
  for (const std::string shard : {"", " --shard 1/2"}) {
    const Result r = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("d.h5")) + shard + " --quiet");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    expect_one_line_error(r, {path("d.h5"), "-o", "another process is writing this output", "d.h5.parts"});
    EXPECT_FALSE(fs::exists(path("d.h5")));
  }
  close(fd);
  const Result r = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("d.h5")) + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(path("d.h5.parts"))) << "the parts directory is removed once the output is assembled";
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
  EXPECT_EQ(r.exit_code, 3) << r.err;  // an error while running: not a crash (139), not bad input (2)
  expect_one_line_error(r, {out});
  EXPECT_EQ(slurp(out), good) << "the old file was replaced";
  const Result v = mcref("export-vdb " + quote(exp) + " -o " + quote((disk / "g.vdb").string()) +
                         " --set geometry.lateral_voxels=128 --set geometry.depth_voxels=128");
  EXPECT_EQ(v.exit_code, 3) << v.err;
  expect_one_line_error(v, {"g.vdb"});
  // A dataset's part, merge's output and validate's tables on the full disk.
  write("ds.toml", "[dataset]\nexperiment = \"s.toml\"\n[[parameter]]\nkey = \"geometry.layer.0.albedo\"\nvalues = [0.2, 0.4]\n");
  const Result d = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote((disk / "d.h5").string()) + " --quiet");
  EXPECT_EQ(d.exit_code, 3) << d.err;
  expect_one_line_error(d, {"d.h5.parts/entry-0.h5", "writing failed"});
  for (const char* shard : {"0/2", "1/2"})
    ASSERT_EQ(mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path(std::string("s") + shard[0] + ".h5")) +
                    " --quiet --shard " + shard).exit_code, 0);
  const Result m = mcref("merge " + quote(path("s0.h5")) + " " + quote(path("s1.h5")) + " -o " + quote((disk / "m.h5").string()));
  EXPECT_EQ(m.exit_code, 3) << m.err;
  expect_one_line_error(m, {"m.h5", "writing failed"});
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"a\"\nexperiment = \"s.toml\"\n");
  const Result s = mcref("validate " + quote(path("suite.toml")) + " -o " + quote((disk / "v").string()) + " --quiet");
  EXPECT_EQ(s.exit_code, 3) << s.err;
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
  // Axes that do not describe the sums (none, or one named twice) are refused; they
  // were read past the end of the sums (a crash in Python, garbage in merge).
  const std::string three = write("three.toml", experiment("tau0 = 0.5\nbeta = 0.8\n", "",
                                                          "quantity = \"tau_plus\"\ntheta_i_deg = [0, 30, 60]\nsamples = 200\n"));
  ASSERT_EQ(mcref("simulate " + quote(three) + " -o " + quote(path("three.h5")) + " --quiet").exit_code, 0);
  std::ofstream(path("three_legacy.h5"), std::ios::binary) << slurp(path("three.h5")).substr(512);
  for (const auto& [axes, piece] : {std::pair<std::string, std::string>{"", "sum holds 3 values, its axes 1 cells"},
                                    {"theta_i,theta_i", "names axis theta_i twice"}}) {
    fs::copy_file(path("three_legacy.h5"), path("axes.h5"), fs::copy_options::overwrite_existing);
    {
      const hid_t f = H5Fopen(path("axes.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      ASSERT_GE(f, 0);
      const hid_t g = H5Gopen2(f, "tau_plus", H5P_DEFAULT);
      ASSERT_GE(H5Adelete(g, "axes"), 0);
      mcref::h5::write_string_attr(g, "axes", axes);
      H5Gclose(g);
      H5Fclose(f);
    }
    expect_one_line_error(mcref("info " + quote(path("axes.h5"))), {"axes.h5", piece});
  }
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

// An existing output that is not a regular file (a FIFO; a device as root) is
// refused before any work by every verb, and by validate and dataset for the
// files they write under their outputs; it is left as it was. (Renaming the
// new file over it would turn /dev/null into a regular file.) `timeout`: a
// reader of a FIFO would wait for a writer forever.
TEST_F(Cli, OutputsThatAreNotRegularFilesAreRefused) {
  const std::string exp = write("x.toml", experiment());
  write("s.toml", slab_experiment());
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"c\"\nexperiment = \"x.toml\"\n");
  write("ds.toml", "[dataset]\nexperiment = \"x.toml\"\n[[parameter]]\nkey = \"geometry.tau0\"\nvalues = [0.3]\n");
  // Inputs each verb accepts: a dataset to merge, a BRDF table dense enough to export.
  ASSERT_EQ(mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("d.h5")) + " --quiet").exit_code, 0);
  std::string brdf = slab_experiment();
  brdf.replace(brdf.find("theta_i_deg = [0, 30, 60]"), 25, "theta_i_deg = [0, 15, 30, 45, 60, 75]");
  ASSERT_EQ(mcref("simulate " + quote(write("b.toml", brdf)) + " -o " + quote(path("t.h5")) +
                  " --quiet --set measure.0.samples=20 --set measure.0.theta_o_bins=8 --set measure.0.phi_bins=8").exit_code, 0);
  const auto run = [&](const std::string& args) { return shell("timeout 60 " + quote(MCREF_BINARY) + " " + args + " --quiet"); };
  std::vector<std::string> specials = {path("fifo")};
  ASSERT_EQ(mkfifo(specials[0].c_str(), 0644), 0);
  if (geteuid() == 0 && mknod(path("null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) specials.push_back(path("null"));
  for (const std::string& sp : specials) {
    const std::string kind = sp == path("fifo") ? "FIFO" : "character device";
    for (const std::string& verb : {"simulate " + quote(exp), "export-vdb " + quote(path("s.toml")),
                                    "merge " + quote(path("d.h5")), "dataset " + quote(path("ds.toml")),
                                    "export-brdf " + quote(path("t.h5")) + " --table brdf --format merl"}) {
      const Result r = run(verb + " -o " + quote(sp));
      EXPECT_EQ(r.exit_code, 2) << verb << ": " << r.err;
      expect_one_line_error(r, {sp, kind, "not a regular file"});
    }
    const auto make_special = [&](const std::string& at) {
      return kind == "FIFO" ? mkfifo(at.c_str(), 0644) : mknod(at.c_str(), S_IFCHR | 0666, makedev(1, 3));
    };
    const auto is_special = [](const std::string& at) {
      const fs::file_type type = fs::symlink_status(at).type();
      return type == fs::file_type::fifo || type == fs::file_type::character;
    };
    // validate's results.json and a case's tables/<case>.h5.
    for (const std::string& name : {"results.json", "tables/c.h5"}) {
      fs::remove_all(path("v"));
      fs::create_directories(path("v/tables"));
      ASSERT_EQ(make_special(path("v/" + name)), 0);
      const Result r = run("validate " + quote(path("suite.toml")) + " -o " + quote(path("v")));
      EXPECT_EQ(r.exit_code, 2) << name << ": " << r.err;
      expect_one_line_error(r, {path("v/" + name), kind});
      EXPECT_TRUE(is_special(path("v/" + name))) << name << " was replaced";
    }
    // A dataset's part, DATA.h5.parts/entry-0.h5, is read to resume: a FIFO
    // there blocked the run, and a device was taken for a damaged part and removed.
    fs::remove_all(path("p.h5.parts"));
    fs::create_directories(path("p.h5.parts"));
    ASSERT_EQ(make_special(path("p.h5.parts/entry-0.h5")), 0);
    const Result part = run("dataset " + quote(path("ds.toml")) + " -o " + quote(path("p.h5")));
    EXPECT_EQ(part.exit_code, 2) << part.err;
    expect_one_line_error(part, {path("p.h5.parts/entry-0.h5"), "not a regular file", "remove it"});
    EXPECT_TRUE(is_special(path("p.h5.parts/entry-0.h5"))) << "the part was replaced";
    EXPECT_FALSE(fs::exists(path("p.h5")));
    EXPECT_TRUE(is_special(sp)) << sp << " was replaced";
  }
  for (const std::string& s : stray({"x.toml", "s.toml", "b.toml", "suite.toml", "ds.toml", "d.h5", "t.h5", "fifo", "null", "v", "p.h5.parts"}))
    ADD_FAILURE() << "left behind: " << s;
}

// A symbolic link given as an output is itself replaced by the new file; the
// file it points to is left as it was (README, "What mcref guarantees").
// An input that is a FIFO blocked the read for ever (`mcref info fifo`,
// `mcref simulate fifo`): refused in one line.
TEST_F(Cli, InputsThatAreNotRegularFilesAreRefused) {
  ASSERT_EQ(mkfifo(path("fifo").c_str(), 0644), 0);
  for (const std::string& verb : {"info " + quote(path("fifo")), "simulate " + quote(path("fifo")) + " -o " + quote(path("t.h5")) + " --quiet"}) {
    const Result r = shell("timeout 20 " + quote(MCREF_BINARY) + " " + verb);
    EXPECT_EQ(r.exit_code, 2) << verb << " (124: it hung): " << r.err;
    expect_one_line_error(r, {"fifo", "is not a regular file"});
  }
  EXPECT_FALSE(fs::exists(path("t.h5")));
}

TEST_F(Cli, AnOutputThatIsALinkIsReplacedNotItsTarget) {
  const std::string exp = write("x.toml", experiment());
  const std::string target = write("target.h5", "keep");
  fs::create_symlink(target, path("link.h5"));
  ASSERT_EQ(mcref("simulate " + quote(exp) + " -o " + quote(path("link.h5")) + " --quiet").exit_code, 0);
  EXPECT_EQ(fs::symlink_status(path("link.h5")).type(), fs::file_type::regular);
  EXPECT_EQ(slurp(target), "keep");
}

// Inputs where validate or dataset write their files are refused before any
// work, naming the input, and left as they were: a suite saved as
// OUTDIR/results.json, an experiment or an included suite in OUTDIR/tables/,
// a dataset's base experiment in DATA.h5.parts/ (it would be removed as a
// damaged part).
TEST_F(Cli, InputsWhereOutputsAreWrittenAreRefused) {
  write("x.toml", experiment());
  const std::string suite = "[suite]\nname = \"s\"\n[[case]]\nname = \"tp\"\nexperiment = \"../x.toml\"\n";
  fs::create_directories(path("o3/tables"));
  const std::string saved = write("o3/results.json", suite);
  Result r = mcref("validate " + quote(saved) + " -o " + quote(path("o3")) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"results.json", "is the input"});
  EXPECT_EQ(slurp(saved), suite);
  fs::remove(saved);
  const std::string inside = write("o3/tables/tp.h5", experiment());
  write("s.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"tp\"\nexperiment = \"o3/tables/tp.h5\"\n");
  r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("o3")) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {inside, "o3/tables"});
  EXPECT_EQ(slurp(inside), experiment());
  write("o3/tables/inc.toml", "[suite]\nname = \"i\"\n[[case]]\nname = \"inc\"\nexperiment = \"../../x.toml\"\n");
  write("s.toml", "[suite]\nname = \"s\"\ninclude = [\"o3/tables/inc.toml\"]\n[[case]]\nname = \"a\"\nexperiment = \"x.toml\"\n");
  r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("o3")) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"inc.toml", "o3/tables"});
  EXPECT_FALSE(fs::exists(path("o3/results.json")));
  // dataset: the base experiment as z.h5.parts/entry-0.h5.
  fs::create_directories(path("z.h5.parts"));
  const std::string part = write("z.h5.parts/entry-0.h5", experiment());
  write("ds.toml", "[dataset]\nexperiment = \"z.h5.parts/entry-0.h5\"\n[[parameter]]\nkey = \"geometry.tau0\"\nvalues = [0.3]\n");
  r = mcref("dataset " + quote(path("ds.toml")) + " -o " + quote(path("z.h5")) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {part, "z.h5.parts"});
  EXPECT_EQ(slurp(part), experiment());
  EXPECT_FALSE(fs::exists(path("z.h5")));
}

// What validate writes under OUTDIR is checked before any case is simulated:
// tables/ must be a directory, results.json and tables/<case>.h5 must not be
// directories. Any verb refuses an output whose temporary name
// <output>.tmp.<pid> would not fit the file system's name limit.
TEST_F(Cli, OutputsThatCouldOnlyFailAfterTheWorkAreRefusedFirst) {
  const std::string exp = write("x.toml", experiment());
  write("suite.toml", "[suite]\nname = \"s\"\n[[case]]\nname = \"c\"\nexperiment = \"x.toml\"\n");
  const auto validate = [&] { return mcref("validate " + quote(path("suite.toml")) + " -o " + quote(path("v")) + " --quiet"); };
  fs::create_directories(path("v"));
  write("v/tables", "a file");
  Result r = validate();
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"v/tables", "not a directory"});
  fs::remove_all(path("v"));  // each case from a fresh OUTDIR (the old code wrote some)
  fs::create_directories(path("v/results.json"));
  r = validate();
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"results.json", "is a directory"});
  EXPECT_FALSE(fs::exists(path("v/tables/c.h5"))) << "the case was simulated first";
  fs::remove_all(path("v"));
  fs::create_directories(path("v/tables/c.h5"));
  r = validate();
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"c.h5", "is a directory"});
  EXPECT_FALSE(fs::exists(path("v/results.json")));
  // A name of NAME_MAX - 2 characters fits, its temporary does not.
  const long max = pathconf(dir_.c_str(), _PC_NAME_MAX);
  if (max <= 0 || max > 1000) GTEST_SKIP() << "no name limit here";
  const std::string name = path(std::string(static_cast<std::size_t>(max) - 5, 'n') + ".h5");
  r = mcref("simulate " + quote(exp) + " -o " + quote(name) + " --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_line_error(r, {"-o", "too long", ".tmp."});
  EXPECT_FALSE(fs::exists(name));
}
