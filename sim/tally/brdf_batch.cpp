#include "sim/tally/brdf_batch.h"

#include <stdexcept>

namespace mcref {

BrdfBatch::BrdfBatch(const BrdfLayout& layout, double paths, std::vector<Table>& tables)
    : l_(layout), paths_(paths), tables_(tables), count_(static_cast<std::size_t>(layout.hemispheres()) * (layout.components() + 3)) {
  const int C = l_.components(), H = l_.hemispheres(), T = l_.theta_o_bins;
  if (tables_.size() < count_ || tables_[0].axes.size() < 2) throw std::logic_error("brdf tables do not match the layout");
  directions_ = tables_[0].axes[0].size() * tables_[0].axes[1].size();  // theta_i x phi_i
  for (std::size_t i = 0; i < count_; ++i) {
    const bool binned = i % (C + 3) <= static_cast<std::size_t>(C);
    const std::size_t per_direction = binned ? static_cast<std::size_t>(T) * l_.phi_bins * 3 : static_cast<std::size_t>(C + 1) * 3;
    if (tables_[i].cells() != 0 && tables_[i].cells() != directions_ * per_direction) throw std::logic_error("brdf table " + tables_[i].name + " does not match the layout");
  }
  seen_.assign(directions_, 0);
  const double fold = l_.folded ? 2.0 : 1.0;
  const double dphi = (l_.folded ? kPi : 2 * kPi) / l_.phi_bins;
  for (int h = 0; h < H; ++h)
    for (int t = 0; t < T; ++t) {
      const double a = static_cast<double>(t) / T, b = static_cast<double>(t + 1) / T;
      const double mu_lo = h == 0 ? 1 - b : a, mu_hi = h == 0 ? 1 - a : b;
      omega_.push_back(fold * 0.5 * (mu_hi * mu_hi - mu_lo * mu_lo) * dphi);
    }
}

void BrdfBatch::add(std::size_t d, const std::vector<double>& s) {
  const int C = l_.components(), H = l_.hemispheres(), T = l_.theta_o_bins, P = l_.phi_bins;
  if (d >= directions_ || seen_[d] || s.size() != l_.sums_size())
    throw std::logic_error("brdf batch: a direction out of range or added twice, or sums of another layout");
  seen_[d] = 1;
  const auto add_cell = [](Table& table, std::size_t i, double x) {
    if (table.sum.empty()) return;  // left out (make_brdf_tables' keep)
    table.sum[i] += x;
    table.sum_sq[i] += x * x;
  };
  for (int h = 0; h < H; ++h) {
    Table* const hemi = &tables_[static_cast<std::size_t>(h) * (C + 3)];  // total, components, albedo, delta
    // Binned f: the total (components added in order) and each component.
    for (int t = 0; t < T; ++t) {
      const double per_unit = paths_ * omega_[static_cast<std::size_t>(h) * T + t];
      for (int p = 0; p < P; ++p)
        for (int k = 0; k < 3; ++k) {
          const std::size_t cell = ((d * T + t) * P + p) * 3 + k;
          double total = 0;
          for (int c = 0; c < C; ++c) {
            const double e = s[((static_cast<std::size_t>(c * H + h) * T + t) * P + p) * 3 + k];
            total += e;
            double part = 0;
            part += e;
            add_cell(hemi[c + 1], cell, part / per_unit);
          }
          add_cell(hemi[0], cell, total / per_unit);
        }
    }
    // Energies per component, then the total (with the unscattered light): all of
    // it (albedo), and that in delta lobes.
    for (int kind = 0; kind < 2; ++kind)
      for (int part = 0; part <= C; ++part)
        for (int k = 0; k < 3; ++k) {
          double e = 0;
          for (int c = 0; c < C; ++c) {
            if (part < C && part != c) continue;
            const std::size_t i = static_cast<std::size_t>(c * H + h) * 3 + k;
            const double non_delta = s[l_.binned_size() + i], in_delta = s[l_.binned_size() + C * H * 3 + i];
            e += kind == 0 ? non_delta + in_delta : in_delta;
          }
          if (part == C) e += s[l_.binned_size() + 2 * C * H * 3 + h * 3 + k];  // unscattered, total only
          add_cell(hemi[C + 1 + kind], (d * (C + 1) + part) * 3 + k, e / paths_);
        }
  }
}

void BrdfBatch::close() {
  for (char seen : seen_)
    if (!seen) throw std::logic_error("brdf batch closed with a direction missing");
  for (std::size_t i = 0; i < count_; ++i)
    if (tables_[i].cells() != 0) ++tables_[i].batches;
  seen_.assign(directions_, 0);
}

void add_brdf_batch(const std::vector<std::vector<double>>& sums, double paths, const BrdfLayout& l, std::vector<Table>& tables) {
  BrdfBatch batch(l, paths, tables);
  for (std::size_t d = 0; d < sums.size(); ++d) batch.add(d, sums[d]);
  batch.close();
}

}  // namespace mcref
