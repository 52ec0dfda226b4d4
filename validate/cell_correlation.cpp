#include "validate/cell_correlation.h"

#include <cmath>
#include <stdexcept>

#include "validate/batch_gram.h"

namespace mcref {

double correlation_square_trace(const std::vector<double>& values, std::size_t per_batch, std::int64_t batches,
                                const std::vector<std::size_t>& cells, const std::vector<double>& w) {
  const std::size_t B = static_cast<std::size_t>(batches), K = cells.size();
  if (batches < 3 || values.size() != B * per_batch || w.size() != K)
    throw std::logic_error("correlation_square_trace: needs 3 batches or more, and batches x cells values");
  const double n = static_cast<double>(batches - 1);
  // x_ib = w_i (y_ib - mean_i) / sqrt(sum_b (y_ib - mean_i)^2): sum_b x_ib x_jb = w_i w_j r_ij.
  std::vector<double> used;
  const std::vector<double> G = batch_gram(values, per_batch, batches, cells, {}, w, &used);
  double sum_w2 = 0, sum_w4 = 0;
  for (double u : used) {
    sum_w2 += u * u;
    sum_w4 += u * u * u * u;
  }
  double frobenius = 0;  // sum_ij (w_i w_j r_ij)^2
  for (double g : G) frobenius += g * g;
  const double off_diagonal = frobenius - sum_w4, pairs = sum_w2 * sum_w2 - sum_w4;
  const double unbiased = (n * off_diagonal - pairs) / (n - 1);
  return static_cast<double>(K) + std::fmax(0.0, unbiased);
}

}  // namespace mcref
