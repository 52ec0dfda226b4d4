#pragma once
// The batches' Gram matrix over a table's cells, which both joint tests of the
// verdicts start from (validate/sign_flip.h, validate/cell_correlation.h).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcref {

// G (batches x batches, row-major), G_bc = sum over `cells` of x_ib x_ic with
// x_ib = w_i (y_ib - c_i) / sqrt(sum_b (y_ib - c_i)^2), y = `values` (batches x
// cells_per_batch, row-major; `cells` are flat indices into a batch), c_i =
// centre[i] or, if `centre` is empty, cell i's mean over the batches, and w_i =
// weights[k] for cells[k] (1 if `weights` is empty). Cells with no spread about
// c_i are left out; the weights of those used are appended to `used_weights`.
std::vector<double> batch_gram(const std::vector<double>& values, std::size_t cells_per_batch, std::int64_t batches,
                               const std::vector<std::size_t>& cells, const std::vector<double>& centre,
                               const std::vector<double>& weights, std::vector<double>* used_weights = nullptr);

}  // namespace mcref
