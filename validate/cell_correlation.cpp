#include "validate/cell_correlation.h"

#include <cmath>
#include <stdexcept>

namespace mcref {

double correlation_square_trace(const std::vector<double>& values, std::size_t per_batch, std::int64_t batches,
                                const std::vector<std::size_t>& cells, const std::vector<double>& w) {
  const std::size_t B = static_cast<std::size_t>(batches), K = cells.size();
  if (batches < 3 || values.size() != B * per_batch || w.size() != K)
    throw std::logic_error("correlation_square_trace: needs 3 batches or more, and batches x cells values");
  const double n = static_cast<double>(batches - 1);
  // x_ib = w_i (y_ib - mean_i) / sqrt(sum_b (y_ib - mean_i)^2): sum_b x_ib x_jb = w_i w_j r_ij.
  std::vector<double> G(B * B, 0.0), x(B);
  double sum_w2 = 0, sum_w4 = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const std::size_t i = cells[k];
    double mean = 0;
    for (std::size_t b = 0; b < B; ++b) mean += values[b * per_batch + i];
    mean /= static_cast<double>(B);
    double ss = 0;
    for (std::size_t b = 0; b < B; ++b) {
      x[b] = values[b * per_batch + i] - mean;
      ss += x[b] * x[b];
    }
    if (!(ss > 0)) continue;  // (no spread: such a cell has no z)
    const double scale = w[k] / std::sqrt(ss);
    for (double& v : x) v *= scale;
    for (std::size_t b = 0; b < B; ++b)
      for (std::size_t c = 0; c <= b; ++c) G[b * B + c] += x[b] * x[c];
    sum_w2 += w[k] * w[k];
    sum_w4 += w[k] * w[k] * w[k] * w[k];
  }
  double frobenius = 0;  // sum_ij (w_i w_j r_ij)^2
  for (std::size_t b = 0; b < B; ++b)
    for (std::size_t c = 0; c <= b; ++c) frobenius += (b == c ? 1.0 : 2.0) * G[b * B + c] * G[b * B + c];
  const double off_diagonal = frobenius - sum_w4, pairs = sum_w2 * sum_w2 - sum_w4;
  const double unbiased = (n * off_diagonal - pairs) / (n - 1);
  return static_cast<double>(K) + std::fmax(0.0, unbiased);
}

}  // namespace mcref
