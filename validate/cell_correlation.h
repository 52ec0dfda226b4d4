#pragma once
// How correlated the z of a table's cells are, from the batches' own values.
//
// The cells of one table share the batches (one batch = one realization of the
// geometry), so their z are correlated, and sum(z^2) over K cells is not
// chi-squared with K degrees of freedom. With R the z's correlation matrix,
// E[sum z^2] = K and Var[sum z^2] = 2 tr(R^2), and Box's approximation (Box
// 1954, Theorem 3.1, as in the Greenhouse-Geisser correction) takes
// sum z^2 ~ c chi2(nu) with c = tr(R^2) / K and nu = K^2 / tr(R^2): nu = K for
// independent cells, 1 for cells that move together.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcref {

// tr(R^2) over the cells `cells` (flat indices into a batch's estimates),
// estimated from `batch_values` (batches x cells_per_batch, row-major): R's
// entries are w_i w_j r_ij, with r_ij the cells' sample correlation over the
// batches and w_i the fraction of cell i's z variance that is the simulation's
// (se / sqrt(se^2 + model_se^2); the model's own noise is independent per
// cell). Each r_ij^2 is corrected for its sampling bias, E[r^2] = 1/n for
// uncorrelated cells (n = batches - 1), by (n r^2 - 1) / (n - 1), which is
// exact at r = 0 and r = 1. Computed from the batches' Gram matrix
// (batches^2 numbers), in O(cells batches^2). At least K; needs batches >= 3.
double correlation_square_trace(const std::vector<double>& batch_values, std::size_t cells_per_batch,
                                std::int64_t batches, const std::vector<std::size_t>& cells,
                                const std::vector<double>& w);

}  // namespace mcref
