#pragma once
// Binning of the light that leaves a sample, shared by every transport
// kind (micrograin fields, microflake slabs, sphere packings).
//
// Bins are equal in solid angle: uniform in cos(theta_o) (|cos| below the
// horizon, for transmission) and in the relative azimuth phi = phi_o - phi_i
// (folded into [0, pi] for isotropic samples). The value of a bin is the
// cosine-weighted bin average of f (1/sr, without the cosine):
//   f_bin = (energy leaving through the bin per unit incident energy) / integral over the bin of |cos theta_o| d omega,
// so a model is compared through the same average.
// Contributions are split into components by scattering order; order 1 is
// further split by where it happened (e.g. grain / base, volume / substrate).
// Delta lobes (exact mirror reflection or unscattered transmission) are kept
// apart as energies, never smeared into a bin.
#include <string>
#include <vector>

#include "models/core/rgb.h"
#include "models/core/vec.h"
#include "sim/tally/azimuth_bins.h"
#include "sim/tally/table.h"

namespace mcref {

struct BrdfLayout {
  int theta_o_bins = 16;   // per hemisphere, uniform in |cos theta_o|
  int phi_bins = 18;
  bool folded = true;      // relative azimuth in [0, pi] (isotropic samples)
  bool transmission = false;  // also tabulate the lower hemisphere (BTDF)
  std::vector<std::string> order1_classes{"single"};  // names of the order-1 split
  // Components: order1_<class>..., order2, order3, order4plus.
  int components() const { return static_cast<int>(order1_classes.size()) + 3; }
  std::vector<std::string> component_names() const;
  int hemispheres() const { return transmission ? 2 : 1; }
  // Sums layout of one incident direction (per channel innermost):
  //   [component][hemisphere][theta_o][phi][3]   binned energy
  //   [component][hemisphere][3]                 total energy (non-delta)
  //   [component][hemisphere][3]                 delta-lobe energy
  //   [hemisphere][3]                            unscattered (order 0) energy
  std::size_t binned_size() const;
  std::size_t sums_size() const;
};

class BrdfAccumulator {
 public:
  BrdfAccumulator(const BrdfLayout& layout, double phi_i, std::vector<double>& sums);
  // A path leaves toward wo (unit; wo.z < 0 is transmission) carrying
  // `weight` per unit incident energy; `order` counts scattering events
  // (0: unscattered, a delta lobe counted in the totals only); `order1_class`
  // indexes layout.order1_classes (used when order == 1).
  void add(Vec3 wo, int order, int order1_class, const Rgb& weight, bool delta);

 private:
  const BrdfLayout& layout_;
  std::vector<double>& sums_;
  // Layout constants, computed once.
  int classes_, H_, T_;
  std::size_t energy_, delta_energy_, unscattered_;
  AzimuthBins phi_bins_;
};

// Tables of a brdf measure: for each hemisphere ("" = reflection, "_btdf"):
//   <name><hemi>                      total f (theta_i, phi_i, theta_o, phi, channel)
//   <name><hemi>_<component>          the same per component
//   <name><hemi>_albedo               energy per (theta_i, phi_i, component + total, channel), delta included
//   <name><hemi>_delta                delta-lobe energy per (theta_i, phi_i, component + total, channel)
// Tables that `keep` does not name (when it names any) are left out: made
// without cells, so they are neither held nor filled (BrdfBatch skips them).
std::vector<Table> make_brdf_tables(const std::string& name, const std::vector<double>& theta_i,
                                    const std::vector<double>& phi_i, const BrdfLayout& layout,
                                    const std::vector<std::string>& keep = {});
// True for the <name><hemi>_delta tables (delta-lobe energies, not densities).
inline bool is_delta_table(const std::string& table_name) {
  const std::string tail = "_delta";
  return table_name.size() >= tail.size() && table_name.compare(table_name.size() - tail.size(), tail.size(), tail) == 0;
}
// (Batches of these tables: sim/tally/brdf_batch.h.)

}  // namespace mcref
