// mcref export-vdb EXPERIMENT.toml -o OUT.vdb: writes each slab layer's density
// grid (sim/volume/density_grid.h) so it opens in Blender or Houdini.
#include <cstdio>

#include "sim/cli/verbs.h"
#include "sim/config/config_error.h"
#include "sim/config/experiment.h"
#include "sim/volume/density_grid.h"

namespace mcref::cli {

namespace {
const char* kHelp =
    "usage: mcref export-vdb EXPERIMENT.toml -o OUT.vdb [--set key=value]...\n"
    "\n"
    "Writes the density grid of every layer of a slab experiment (kind = \"slab\")\n"
    "as an OpenVDB fog volume named layer<k>_density: a periodic lateral tile of side\n"
    "geometry.tile (geometry.lateral_voxels per side), geometry.depth_voxels voxel\n"
    "intervals per layer in depth, the stack's top face at z = 0, layers below it.\n"
    "The layer's parameters (phase, alpha, orientation, albedo, f0) are grid metadata.\n"
    "The grids are built whatever geometry.backend says.\n";
}  // namespace

int export_vdb(const std::vector<std::string>& raw) {
  Args a = parse_args(raw, "export-vdb", true);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref export-vdb needs exactly one EXPERIMENT.toml (see --help)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output file is required (-o OUT.vdb)");
  const Experiment ex = load_experiment(a.positional[0], a.sets);
  if (ex.kind != "slab")
    throw ConfigError(ex.file, "geometry.kind", "export-vdb writes slab density grids; \"" + ex.kind + "\" is not supported yet");
  const volume::DensityGrids grids(ex.slab);
  const std::string tmp = a.output + ".tmp";
  volume::write_vdb(tmp, grids);
  if (std::rename(tmp.c_str(), a.output.c_str()) != 0) throw ConfigError("command line", "-o", "cannot write " + a.output);
  if (!a.quiet) std::fprintf(stderr, "mcref export-vdb: %zu grids -> %s\n", grids.grids().size(), a.output.c_str());
  return 0;
}

}  // namespace mcref::cli
