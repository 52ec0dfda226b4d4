#include "sim/slab/escape.h"

#include <cmath>
#include <stdexcept>

#include "sim/slab/residual_ratio_tracking.h"

namespace mcref::volume {

namespace {

// Calls visit(k, from, to) for each layer k the ray from (layer, depth) along d
// crosses to the face it leaves by (d.z != 0), in order: it enters k at depth
// `from` and leaves it at depth `to`.
template <class Visit>
void for_each_layer_crossed(const std::vector<MediumLayer>& layers, int layer, double depth, Vec3 d, Visit visit) {
  const int step = d.z > 0 ? -1 : 1, end = d.z > 0 ? -1 : static_cast<int>(layers.size());
  for (int k = layer; k != end; k += step) {
    const MediumLayer& l = layers[k];
    visit(k, k == layer ? depth : d.z > 0 ? l.bottom : l.top, d.z > 0 ? l.top : l.bottom);
  }
}

bool varies_laterally(const SlabMedium& medium, int k) { return medium.grids() && !medium.depth_profiles()[k]; }

// The optical depth of layer k between depths `from` and `to` along d (inv_mu =
// 1 / |d.z|), for a homogeneous layer or one varying in depth only.
double exact_optical_depth(const SlabMedium& medium, int k, double from, double to, Vec3 d, double inv_mu) {
  if (medium.grids()) {
    // sigma(d) as the layer's free flights take it (the grids' S).
    const double column = medium.depth_profiles()[k]->column_to_face(from, d.z < 0);
    return column > 0 ? medium.majorants()[k].factor(d) * column * inv_mu : 0.0;
  }
  const MediumLayer& l = medium.layers()[k];
  return l.density > 0 ? l.density * l.phase->sigma(d) * (std::fabs(to - from) * inv_mu) : 0.0;
}

// The optical depth from (layer, depth) along d to the face the ray leaves by
// (d.z != 0), in closed form: exact through the layers varying in depth only (and
// homogeneous layers), the control part (sim/slab/residual_ratio_tracking.h)
// through laterally varying ones; `lateral` says whether the ray crosses any.
double closed_form_optical_depth(const SlabMedium& medium, int layer, double depth, Vec3 d, bool& lateral) {
  const double inv_mu = 1 / std::fabs(d.z);
  double tau = 0;
  lateral = false;
  for_each_layer_crossed(medium.layers(), layer, depth, d, [&](int k, double from, double to) {
    if (!varies_laterally(medium, k)) {
      tau += exact_optical_depth(medium, k, from, to, d, inv_mu);
      return;
    }
    const LayerMajorants& M = medium.majorants()[k];
    if (M.s_varies) throw std::invalid_argument(escape_unsupported(medium));
    lateral = true;
    if (const double column = control_column(M, from, to); column > 0) tau += M.factor(d) * column * inv_mu;
  });
  return tau;
}

}  // namespace

double escape_probability(const SlabMedium& medium, int layer, double depth, Vec3 d) {
  if (d.z == 0 || (d.z < 0 && medium.has_substrate())) return 0;
  bool lateral = false;
  const double tau = closed_form_optical_depth(medium, layer, depth, d, lateral);
  if (lateral)
    throw std::invalid_argument("escape_probability: the ray crosses a laterally varying layer; its escape is "
                                "estimated (escape_estimate)");
  return std::exp(-tau);
}

double escape_estimate(const SlabMedium& medium, const Photon& p, Vec3 d, Rng& rng) {
  if (d.z == 0 || (d.z < 0 && medium.has_substrate())) return 0;
  bool lateral = false;
  double estimate = std::exp(-closed_form_optical_depth(medium, p.layer, p.depth, d, lateral));
  if (!lateral) return estimate;
  // The residual parts of the laterally varying layers, tracked.
  for_each_layer_crossed(medium.layers(), p.layer, p.depth, d, [&](int k, double from, double to) {
    if (estimate > 0 && varies_laterally(medium, k))
      estimate = track_residual(medium.majorants()[k], *medium.voxels(), k, p, d, from, to, estimate, rng);
  });
  return estimate;
}

std::string escape_unsupported(const SlabMedium& medium) {
  for (std::size_t k = 0; k < medium.majorants().size(); ++k)
    if (medium.majorants()[k].s_varies)
      return "the next-event estimators need every OpenVDB layer to have one SGGX matrix; layer " + std::to_string(k) +
             "'s S varies";
  return "";
}

}  // namespace mcref::volume
