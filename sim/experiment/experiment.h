#pragma once
// An experiment file (TOML), validated: geometry, run settings and the list
// of measures. Every error names the file, the key and the allowed range.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/files/input_file.h"
#include "sim/micrograin/micrograin_geometry.h"
#include "sim/micrograin/micrograin_materials.h"
#include "sim/slab/slab_geometry.h"
#include "sim/spheres/sphere_packing.h"

namespace mcref {

struct RunSettings {
  std::uint64_t seed = 1;
  int batches = 16;  // independent realizations of the random geometry
  int threads = 0;   // 0: all cores
};

// One [[measure]] table. Angles are stored in radians.
struct Measure {
  std::string quantity;  // p1, ndf, tau_plus, tau_height, g1, pore_visibility, vndf, phi_conditional
  std::string name;      // table name in the output file (defaults to quantity)
  std::vector<double> theta_i, phi_i;  // incident directions
  std::vector<double> theta_o, phi;    // pore_visibility: outgoing directions, relative azimuths
  std::vector<double> theta_m;         // phi_conditional: unit-space polar angles of the normals
  int theta_o_bins = 0, phi_bins = 0;  // brdf: outgoing bins (equal solid angle)
  int max_order = 0;                   // brdf: 0 = unlimited (unbiased Russian roulette)
  int mu_bins = 0;                     // phase: bins of the deflection cosine
  int theta_m_bins = 0, phi_m_bins = 0;  // normal-space bins
  int r_bins = 0;                        // p1
  double r_max = 0;                      // p1, in grain radii
  int h_points = 0;                      // tau_height
  std::int64_t samples = 0;              // per batch (and per direction where directions apply)
};

struct Experiment {
  std::string file;  // where it came from (for messages)
  std::string text;  // the effective configuration (after --set), stored as provenance
  std::vector<InputFile> inputs;  // the other files it read (geometry.density_vdb): never an output
  std::string kind;  // geometry kind: "micrograin", "slab" or "spheres"
  MicrograinGeometry micrograin;
  MicrograinMaterials materials;  // micrograin transport only
  SlabGeometry slab;
  SpherePacking spheres;
  bool isotropic = true;  // the sample's statistics are symmetric in azimuth
  RunSettings run;
  std::vector<Measure> measures;
};

// The quantities a geometry kind can measure.
const std::vector<std::string>& known_quantities(const std::string& kind);

// Parses and validates; `overrides` are --set key=value assignments.
Experiment parse_experiment(const std::string& text, const std::string& file,
                            const std::vector<std::string>& overrides = {});
// Reads the file first (error if unreadable).
Experiment load_experiment(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace mcref
