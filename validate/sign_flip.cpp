#include "validate/sign_flip.h"

#include <cmath>
#include <stdexcept>

#include "models/core/rng.h"
#include "validate/batch_gram.h"

namespace mcref {

double sign_flip_smallest_p(std::int64_t batches) {
  if (batches <= kExactBatches) return std::ldexp(1.0, -static_cast<int>(batches - 1));
  return 1.0 / static_cast<double>(kRandomFlips + 1);
}

double sign_flip_p_value(const std::vector<double>& values, std::size_t per_batch, std::int64_t batches,
                         const std::vector<std::size_t>& cells, const std::vector<double>& model) {
  const std::size_t B = static_cast<std::size_t>(batches);
  if (batches < 2 || batches > kMaxFlipBatches || values.size() != B * per_batch)
    throw std::logic_error("sign_flip_p_value: needs 2 to 64 batches, and batches x cells values");
  // G_bc = sum_i x_ib x_ic with x_ib = d_ib / sqrt(sum_b d_ib^2), d = values - model: T(eps) = eps' G eps.
  const std::vector<double> G = batch_gram(values, per_batch, batches, cells, model, {});
  double observed = 0, bound = 0;  // |T| <= sum |G| for every pattern
  for (double g : G) {
    observed += g;
    bound += std::fabs(g);
  }
  // Ties count as at least as large, and so does anything within the rounding of T
  // along the walk below (about 1e-16 sum |G| a step; 32767 steps at most).
  const double at_least = observed - 1e-9 * bound;
  std::size_t count = 1, patterns = 1;  // the observed pattern
  if (batches <= kExactBatches) {
    // Every pattern with eps_0 = +1, in Gray-code order: flipping eps_j changes T by
    // -4 eps_j (G eps)_j + 4 G_jj, and G eps by -2 eps_j G_.j.
    std::vector<double> eps(B, 1.0), v(B, 0.0);
    for (std::size_t b = 0; b < B; ++b)
      for (std::size_t c = 0; c < B; ++c) v[b] += G[b * B + c];
    double T = observed;
    const std::uint64_t n = std::uint64_t{1} << (B - 1);
    for (std::uint64_t k = 1; k < n; ++k) {
      const std::size_t j = 1 + static_cast<std::size_t>(__builtin_ctzll(k));  // (eps_0 stays +1)
      T += -4 * eps[j] * v[j] + 4 * G[j * B + j];
      for (std::size_t b = 0; b < B; ++b) v[b] -= 2 * eps[j] * G[b * B + j];
      eps[j] = -eps[j];
      count += T >= at_least;
    }
    patterns = n;
  } else {
    Rng rng(0x5167'6e2d'666c'6970ULL);  // fixed: the same p on every run
    std::vector<double> eps(B);
    for (std::size_t m = 0; m < kRandomFlips; ++m) {
      const std::uint64_t bits = rng.next_u64();
      for (std::size_t b = 0; b < B; ++b) eps[b] = (bits >> b) & 1 ? 1.0 : -1.0;
      double T = 0;
      for (std::size_t b = 0; b < B; ++b) {
        double row = 0;
        for (std::size_t c = 0; c < B; ++c) row += G[b * B + c] * eps[c];
        T += eps[b] * row;
      }
      count += T >= at_least;
    }
    patterns = kRandomFlips + 1;
  }
  return static_cast<double>(count) / static_cast<double>(patterns);
}

}  // namespace mcref
