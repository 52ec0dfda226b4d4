#pragma once
// One batch of the tables of make_brdf_tables (sim/tally/brdf_tally.h), added
// one incident direction at a time as its sums come in. A table's cells are
// independent (sum += x, sum_sq += x^2 per cell), so adding a direction's cells
// as soon as they are known gives the same bits as adding the whole batch at
// once, without holding every direction's sums (for 32 x 32 directions and
// 32 x 32 bins, hundreds of MB a batch). Tables left out (made without cells,
// make_brdf_tables' `keep`) are left alone.
#include <cstddef>
#include <vector>

#include "sim/tally/brdf_tally.h"
#include "sim/tally/table.h"

namespace mcref {

class BrdfBatch {
 public:
  // `paths`: paths per incident direction; `tables` begins with those of
  // make_brdf_tables, in its order (tables after them are left alone).
  BrdfBatch(const BrdfLayout& layout, double paths, std::vector<Table>& tables);
  // Adds the sums of incident direction `direction` (theta_i index * phi_i count +
  // phi_i index; BrdfLayout::sums_size() values) to every table.
  void add(std::size_t direction, const std::vector<double>& sums);
  // Counts the batch in every table (every direction must have been added) and
  // starts the next one.
  void close();

 private:
  BrdfLayout l_;
  double paths_;
  std::vector<Table>& tables_;
  std::size_t count_;          // make_brdf_tables' tables: per hemisphere, total, components, albedo, delta
  std::vector<double> omega_;  // per hemisphere and theta_o bin: the bin's projected solid angle
  std::size_t directions_;
  std::vector<char> seen_;  // per direction: added in this batch
};

// All directions at once: `sums_per_direction[d]` is direction d's.
void add_brdf_batch(const std::vector<std::vector<double>>& sums_per_direction, double paths,
                    const BrdfLayout& layout, std::vector<Table>& tables);

}  // namespace mcref
