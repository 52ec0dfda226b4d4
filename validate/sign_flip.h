#pragma once
// The sign-flip test of a table against a model: exact for cells correlated in
// any way (they share batches), with no estimate of the correlation.
//
// Under the model, each batch's deviations d_b = (estimates of batch b) -
// model are independent over batches and symmetric about 0 (a batch estimate is
// a mean of many samples), so flipping the sign of whole batches leaves their
// joint distribution unchanged. The statistic T = sum over cells i of
// (sum_b d_ib)^2 / sum_b d_ib^2 (a sum of t_i^2 / (1 + t_i^2 / (batches - 1))
// times batches / (batches - 1)) is compared with its values under every sign
// pattern (batches <= kExactBatches: all 2^(batches-1), up to the overall sign)
// or under kRandomFlips random ones: p = the fraction at least as large, the
// observed one counted (Fisher's randomization test; e.g. Winkler et al. 2014,
// "Permutation inference for the general linear model", sign flipping).
// The smallest p it can give is 1 / 2^(batches-1) (1 / (kRandomFlips + 1) above
// kExactBatches): validate/metrics.h uses it from kMinFlipBatches to
// kMaxFlipBatches batches (p down to 3e-5), Box's approximation otherwise.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcref {

constexpr std::int64_t kMinFlipBatches = 16;
constexpr std::int64_t kExactBatches = 16;
constexpr std::int64_t kMaxFlipBatches = 64;  // (one random 64-bit word per pattern; O(batches^2) each)
constexpr std::size_t kRandomFlips = 32767;

// p-value over the cells `cells` (flat indices into a batch's estimates) of
// `batch_values` (batches x cells_per_batch, row-major) against `model` (per
// cell of a batch). Deterministic (a fixed seed for the random flips).
double sign_flip_p_value(const std::vector<double>& batch_values, std::size_t cells_per_batch, std::int64_t batches,
                         const std::vector<std::size_t>& cells, const std::vector<double>& model);

// The smallest p-value the test can give with `batches` batches.
double sign_flip_smallest_p(std::int64_t batches);

}  // namespace mcref
