#include "sim/tally/brdf_tally.h"

#include <algorithm>
#include <cmath>

namespace mcref {

std::vector<std::string> BrdfLayout::component_names() const {
  std::vector<std::string> n;
  for (const std::string& c : order1_classes) n.push_back("order1_" + c);
  n.insert(n.end(), {"order2", "order3", "order4plus"});
  return n;
}

std::size_t BrdfLayout::binned_size() const {
  return static_cast<std::size_t>(components()) * hemispheres() * theta_o_bins * phi_bins * 3;
}

std::size_t BrdfLayout::sums_size() const {
  return binned_size() + (2 * static_cast<std::size_t>(components()) + 1) * hemispheres() * 3;
}

BrdfAccumulator::BrdfAccumulator(const BrdfLayout& layout, double phi_i, std::vector<double>& sums)
    : layout_(layout),
      sums_(sums),
      classes_(static_cast<int>(layout.order1_classes.size())),
      H_(layout.hemispheres()),
      T_(layout.theta_o_bins),
      energy_(layout.binned_size()),
      delta_energy_(energy_ + static_cast<std::size_t>(layout.components()) * H_ * 3),
      unscattered_(energy_ + 2 * static_cast<std::size_t>(layout.components()) * H_ * 3),
      phi_bins_(layout.phi_bins, phi_i, layout.folded) {}

void BrdfAccumulator::add(Vec3 wo, int order, int order1_class, const Rgb& weight, bool delta) {
  const int c = order <= 1 ? order1_class : classes_ + std::min(order, 4) - 2;
  const int h = wo.z >= 0 ? 0 : 1;
  if (h == 1 && !layout_.transmission) return;
  if (order == 0) {  // unscattered: a delta lobe in the total, in no component
    for (int k = 0; k < 3; ++k) sums_[unscattered_ + h * 3 + k] += weight[k];
    return;
  }
  const std::size_t ch = static_cast<std::size_t>(c * H_ + h) * 3;
  const std::size_t energy = (delta ? delta_energy_ : energy_) + ch;
  for (int k = 0; k < 3; ++k) sums_[energy + k] += weight[k];
  if (delta) return;
  const double mu = std::fabs(wo.z);
  const int t = std::min(T_ - 1, static_cast<int>((h == 0 ? 1 - mu : mu) * T_));
  const int p = phi_bins_.bin(wo);
  const std::size_t bin = ((static_cast<std::size_t>(c * H_ + h) * T_ + t) * layout_.phi_bins + p) * 3;
  for (int k = 0; k < 3; ++k) sums_[bin + k] += weight[k];
}

namespace {

Axis theta_o_axis(const BrdfLayout& l, int hemisphere) {
  std::vector<double> e(l.theta_o_bins + 1);
  for (int k = 0; k <= l.theta_o_bins; ++k) {
    const double u = static_cast<double>(k) / l.theta_o_bins;
    e[k] = hemisphere == 0 ? std::acos(1 - u) : kPi - std::acos(u);
  }
  return Axis::bins("theta_o", "rad", e);
}

// A table with its cells, or without them if `keep` names tables but not this one.
Table kept_or_left_out(std::string name, std::string quantity, std::vector<Axis> axes, const std::vector<std::string>& keep) {
  if (keep.empty() || std::find(keep.begin(), keep.end(), name) != keep.end())
    return Table(std::move(name), std::move(quantity), std::move(axes));
  Table t;
  t.name = std::move(name);
  t.quantity = std::move(quantity);
  t.axes = std::move(axes);
  return t;
}

}  // namespace

std::vector<Table> make_brdf_tables(const std::string& name, const std::vector<double>& theta_i,
                                    const std::vector<double>& phi_i, const BrdfLayout& l,
                                    const std::vector<std::string>& keep) {
  std::vector<Table> out;
  const Axis ti = Axis::points("theta_i", "rad", theta_i), pi = Axis::points("phi_i", "rad", phi_i);
  const Axis phi = Axis::uniform_bins("phi", "rad", 0, l.folded ? kPi : 2 * kPi, l.phi_bins);
  const Axis channel = Axis::points("channel", "RGB index", {0, 1, 2});
  std::vector<double> comps(l.components() + 1);
  for (int c = 0; c <= l.components(); ++c) comps[c] = c;
  std::string names;
  for (const std::string& n : l.component_names()) names += n + ",";
  names += "total";
  for (int h = 0; h < l.hemispheres(); ++h) {
    const std::string base = name + (h == 0 ? "" : "_btdf");
    const std::string what = h == 0 ? "BRDF" : "BTDF";
    std::vector<std::string> parts{"total"};
    for (const std::string& c : l.component_names()) parts.push_back(c);
    for (const std::string& part : parts) {
      Table t = kept_or_left_out(part == "total" ? base : base + "_" + part, h == 0 ? "brdf" : "btdf",
                                 {ti, pi, theta_o_axis(l, h), phi, channel}, keep);
      t.units = "1/sr";
      t.description = what + " f (without the cosine), cosine-weighted bin average; " +
                      (part == "total" ? std::string("all orders, delta lobes excluded") : "component " + part);
      t.attributes["component"] = part;
      t.attributes["cosine_included"] = "false";
      t.attributes["phi"] = l.folded ? "phi_o - phi_i folded into [0, pi]; 0 = back toward the light"
                                     : "phi_o - phi_i in [0, 2pi); 0 = back toward the light";
      t.attributes["delta_lobes"] = "excluded from the bins; their energy is in " + base + "_delta";
      out.push_back(std::move(t));
    }
    for (const char* kind : {"_albedo", "_delta"}) {
      Table t = kept_or_left_out(base + kind, h == 0 ? "albedo" : "transmittance",
                                 {ti, pi, Axis::points("component", "index", comps), channel}, keep);
      t.units = "1";
      t.description = std::string(kind) == "_albedo"
                          ? what + " directional energy per component (delta lobes included)"
                          : what + " energy in delta lobes (exact mirror / unscattered) per component";
      t.attributes["components"] = names;
      t.attributes["total"] = "every path; the unscattered light (order 0) is in the total only, in no component";
      out.push_back(std::move(t));
    }
  }
  return out;
}

}  // namespace mcref
