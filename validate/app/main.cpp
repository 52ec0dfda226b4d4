// mcref: the command-line front end; one file per verb (validate/app/*_verb.cpp).
#include <hdf5.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "sim/experiment/config_error.h"
#include "sim/hdf5/table_file.h"
#include "sim/parallel/communicator.h"
#include "validate/app/verbs.h"

namespace {

const char* kUsage =
    "mcref: Monte Carlo ground truth for analytic BRDF models of porous microstructures\n"
    "\n"
    "usage: mcref <verb> [options]\n"
    "  simulate EXPERIMENT.toml -o TABLES.h5   simulate an experiment, write its tables\n"
    "  validate SUITE.toml -o OUTDIR           run a validation suite, write its tables and results\n"
    "                                          (plots and report: scripts/, see validate --help)\n"
    "  info TABLES.h5                          print the tables, axes, sample counts and provenance\n"
    "  export-vdb EXPERIMENT.toml -o OUT.vdb   write a slab's layer grids or a micrograin field (OpenVDB)\n"
    "  export-brdf TABLES.h5 --table NAME --format merl -o OUT.binary\n"
    "                                          write a BRDF table as a MERL file\n"
    "  dataset DATASET.toml -o DATA.h5         simulate every entry of a parameter sweep (--shard K/N)\n"
    "  merge SHARD.h5... -o DATA.h5            combine dataset shards into one file\n"
    "\n"
    "`mcref <verb> --help` explains each verb; `mcref --version` prints the version and commit.\n"
    "Exit status: 0 done; 1 validate: a check failed; 2 bad input (nothing run, nothing written);\n"
    "3 an error while running (a full disk, an unwritable output; no output left half-written).\n";

// An error met while running (not the input's fault): exit 3, so that a
// script can tell it from validate's failed check (1) and from bad input (2).
constexpr int kRunError = 3;

// Under MPI, an error met while checking the input joins the ranks'
// agreement (a rank may have met it alone), and rank 0 prints the one every
// rank agreed on; an error one rank met alone while the others wait for it
// ends the job.
int fail(int code, const char* what) {
  const mcref::Communicator& world = mcref::Communicator::world();
  if (world.size() > 1 && mcref::DistributedStep::broken()) {
    std::fprintf(stderr, "mcref: error (rank %d of %d): %s\n", world.rank(), world.size(), what);
    std::fflush(stderr);
    mcref::MpiSession::abort(code);
  }
  const std::string agreed = mcref::join_agreement(what);
  if (world.root()) std::fprintf(stderr, "mcref: error: %s\n", agreed.c_str());
  return code;
}

// The exit code, or kRunError if what was printed on stdout could not all be written
// (a full disk, a closed pipe): `mcref info > /dev/full` must not succeed.
int checked_stdout(int code) {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return code;
  return code ? code : fail(kRunError, "could not write to standard output");
}

int run(const std::string& verb, const std::vector<std::string>& args, const std::string& command_line) {
  if (verb == "simulate") return mcref::cli::simulate(args, command_line);
  if (verb == "validate") return mcref::cli::validate(args, command_line);
  if (verb == "info") return mcref::cli::info(args);
  if (verb == "export-vdb") return mcref::cli::export_vdb(args);
  if (verb == "export-brdf") return mcref::cli::export_brdf(args);
  if (verb == "dataset") return mcref::cli::dataset(args, command_line);
  if (verb == "merge") return mcref::cli::merge(args);
  return fail(2, ("unknown verb '" + verb + "' (allowed: simulate, validate, info, export-vdb, export-brdf, dataset, merge)").c_str());
}

}  // namespace

int main(int argc, char** argv) {
  // HDF5's exit-time cleanup closes again a file whose close failed (a full
  // disk) and crashes; every mcref file is closed explicitly, so it is not needed.
  H5dont_atexit();
  // MPI for the verbs that spread their work over ranks; under a launcher, the
  // others (info, merge, the exports, help) run on rank 0 alone.
  bool spread = argc > 1 && (std::strcmp(argv[1], "simulate") == 0 || std::strcmp(argv[1], "validate") == 0 ||
                             std::strcmp(argv[1], "dataset") == 0);
  for (int i = 2; i < argc; ++i)
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) spread = false;
  const mcref::MpiSession mpi(&argc, &argv, spread);
  if (!spread && mcref::MpiSession::launcher_rank() > 0) return 0;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : checked_stdout(0);
  }
  if (args[0] == "--version") {
    std::printf("mcref %s (commit %s)\n", mcref::mcref_version().c_str(), mcref::mcref_git_commit().c_str());
    return checked_stdout(0);
  }
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
  const std::string verb = args[0];
  args.erase(args.begin());
  try {
    return checked_stdout(run(verb, args, command_line));
  } catch (const mcref::ConfigError& e) {
    return fail(2, e.what());
  } catch (const std::exception& e) {
    return fail(kRunError, e.what());
  }
}
