// mcref export-vdb EXPERIMENT.toml -o OUT.vdb: writes a slab's grids
// (sim/slab/density_grid.h) or one realization of a micrograin field
// (sim/micrograin/micrograin_vdb.h) so they open in Blender or Houdini.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/files/output_path.h"
#include "sim/micrograin/micrograin_vdb.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/slab_vdb.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

namespace {
const char* kHelp =
    "usage: mcref export-vdb EXPERIMENT.toml -o OUT.vdb [--seed N] [--voxel-size H] [--set key=value]...\n"
    "\n"
    "Slab experiments (kind = \"slab\"): every layer's density grid, an OpenVDB fog\n"
    "volume named layer<k>_density: a periodic lateral tile of side geometry.tile\n"
    "(geometry.lateral_voxels voxels per side, the seam stored once: voxel i = N\n"
    "would repeat i = 0), geometry.depth_voxels + 1 voxel planes per layer in depth,\n"
    "the stack's top face at z = 0, layers below it. SGGX layers add their matrix\n"
    "field S on the same voxels as two Vec3s (float32) grids, layer<k>_S_diag =\n"
    "(S_xx, S_yy, S_zz) and layer<k>_S_offdiag = (S_xy, S_xz, S_yz). The layer's\n"
    "parameters (phase, alpha, orientation, albedo, f0) are grid metadata. The grids\n"
    "are built whatever geometry.backend says.\n"
    "\n"
    "Micrograin experiments (kind = \"micrograin\"): realization 0 of run.seed (the\n"
    "field simulate uses first) as a fog volume named grains: 1 where the voxel\n"
    "centre lies inside a grain, 0 outside, over the periodic tile and z in [0, c].\n"
    "Metadata: tau0, beta_x, beta_y, radius, tile, tile_side, c, seed (run.seed),\n"
    "realization (0), grain_count.\n"
    "  --voxel-size H   voxel size in real units (default radius / 8); refused if the\n"
    "                   grid would hold more than 2e8 voxels\n"
    "  --seed N         overrides run.seed\n";
}  // namespace

int export_vdb(const std::vector<std::string>& raw) {
  // --voxel-size is export-vdb's own option; the rest goes to the shared parser.
  std::vector<std::string> rest;
  double voxel_size = 0;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != "--voxel-size") {
      rest.push_back(raw[i]);
      continue;
    }
    if (i + 1 >= raw.size()) throw ConfigError("command line", "--voxel-size", "needs a value");
    given_once(seen, "--voxel-size", "--voxel-size");
    const std::string& v = raw[++i];
    char* end = nullptr;
    voxel_size = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !(voxel_size > 0) || !(voxel_size < 1e30))
      throw ConfigError("command line", "--voxel-size", "= " + v + " must be a positive number");
  }
  Args a = parse_args(rest, "export-vdb", true);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref export-vdb needs exactly one EXPERIMENT.toml (see --help)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output file is required (-o OUT.vdb)");
  std::vector<std::string> sets = a.sets;
  if (a.seed >= 0) sets.push_back("run.seed=" + std::to_string(a.seed));
  const Experiment ex = load_experiment(a.positional[0], sets);
  check_output_file(a.output, with_inputs({a.positional[0]}, ex.inputs));
  std::size_t written = 0;
  if (ex.kind == "slab") {
    if (voxel_size > 0) throw ConfigError("command line", "--voxel-size", "applies to micrograin fields; slabs use geometry.lateral_voxels and geometry.depth_voxels");
    const volume::DensityGrids grids(ex.slab);
    volume::write_vdb(a.output, grids);
    written = grids.all_grids().size();
  } else if (ex.kind == "micrograin") {
    const MicrograinVoxels v = micrograin_voxels(ex.micrograin, voxel_size);
    if (v.count() > kMaxMicrograinVoxels)
      throw ConfigError("command line", "--voxel-size",
                        "the grain grid would hold " + voxel_count_text(v) +
                            " voxels (more than 2e8); give a larger --voxel-size (real units) or a smaller geometry.tile");
    const MicrograinField field(ex.micrograin, micrograin_realization_seed(ex.run.seed, 0));
    write_micrograin_vdb(a.output, micrograin_grid(field, v, ex.run.seed, 0));
    written = 1;
  } else {
    throw ConfigError(ex.file, "geometry.kind", "export-vdb writes slab and micrograin grids; \"" + ex.kind + "\" is not supported");
  }
  if (!a.quiet) std::fprintf(stderr, "mcref export-vdb: %zu grids -> %s\n", written, a.output.c_str());
  return 0;
}

}  // namespace mcref::cli
