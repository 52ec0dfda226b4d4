#include "validate/batch_gram.h"

#include <cmath>

namespace mcref {

std::vector<double> batch_gram(const std::vector<double>& values, std::size_t per_batch, std::int64_t batches,
                               const std::vector<std::size_t>& cells, const std::vector<double>& centre,
                               const std::vector<double>& weights, std::vector<double>* used_weights) {
  const std::size_t B = static_cast<std::size_t>(batches);
  std::vector<double> G(B * B, 0.0), x(B);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::size_t i = cells[k];
    double c = 0;
    if (centre.empty()) {
      for (std::size_t b = 0; b < B; ++b) c += values[b * per_batch + i];
      c /= static_cast<double>(B);
    } else {
      c = centre[i];
    }
    double ss = 0;
    for (std::size_t b = 0; b < B; ++b) {
      x[b] = values[b * per_batch + i] - c;
      ss += x[b] * x[b];
    }
    if (!(ss > 0)) continue;
    const double w = weights.empty() ? 1.0 : weights[k], scale = w / std::sqrt(ss);
    for (double& v : x) v *= scale;
    for (std::size_t b = 0; b < B; ++b)
      for (std::size_t d = 0; d < B; ++d) G[b * B + d] += x[b] * x[d];
    if (used_weights) used_weights->push_back(w);
  }
  return G;
}

}  // namespace mcref
