// mcref.sggx (continued): SpongeCake's multiple-scattering lobes (Wang et al.
// 2022 Sec. 5; models/sggx/multiple_scattering_lobes.h), vectorised over
// directions: FlakeLayer (the dataset's layer parameters, RGB), ModifiedLayer,
// MultipleScatteringLobes, flake_stack and spongecake_ms_bsdf.
#include <stdexcept>

#include "models/sggx/multiple_scattering_lobes.h"
#include "sim/experiment/config_error.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace {

Rgb rgb(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }
std::array<double, 3> array3(const Rgb& v) { return {v.r, v.g, v.b}; }

sggx::FlakeType flake_type(const std::string& s) {
  if (s == "surface") return sggx::FlakeType::kSurface;
  if (s == "fiber") return sggx::FlakeType::kFiber;
  throw ConfigError("<python>", "type", "'" + s + "' is not a flake type (allowed: surface, fiber)");
}

template <class F>
auto checked(F f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw ConfigError(e.what());
  }
}

}  // namespace

void bind_spongecake_lobes(py::module_& root) {
  py::module_ m = root.attr("sggx").cast<py::module_>();
  using sggx::FlakeLayer;
  using sggx::ModifiedLayer;
  using sggx::MultipleScatteringLobes;

  py::class_<FlakeLayer>(m, "FlakeLayer",
                         "One SGGX flake layer with RGB albedo and f0 (SpongeCake Sec. 5 parameters).\n"
                         "type: 'surface' or 'fiber'; orientation omega_p (normalised here).")
      .def(py::init([](const std::string& type, double alpha, double thickness, double density,
                       std::array<double, 3> albedo, std::array<double, 3> f0, std::array<double, 3> orientation) {
             FlakeLayer l{flake_type(type), alpha, thickness, density, rgb(albedo), rgb(f0),
                          {orientation[0], orientation[1], orientation[2]}};
             checked([&] { sggx::check_flake_layer(l, "FlakeLayer"); return 0; });
             return l;
           }),
           py::arg("type"), py::arg("alpha"), py::arg("thickness"), py::arg("density") = 1.0,
           py::arg("albedo") = std::array<double, 3>{1, 1, 1}, py::arg("f0") = std::array<double, 3>{1, 1, 1},
           py::arg("orientation") = std::array<double, 3>{0, 0, 1})
      .def_property_readonly("type", [](const FlakeLayer& l) { return l.type == sggx::FlakeType::kFiber ? "fiber" : "surface"; })
      .def_readonly("alpha", &FlakeLayer::alpha)
      .def_readonly("thickness", &FlakeLayer::thickness)
      .def_readonly("density", &FlakeLayer::density)
      .def_property_readonly("albedo", [](const FlakeLayer& l) { return array3(l.albedo); })
      .def_property_readonly("f0", [](const FlakeLayer& l) { return array3(l.f0); });

  py::class_<ModifiedLayer>(m, "ModifiedLayer", "Modified parameters alpha', T', gamma' (RGB), f0' (RGB) of one layer.")
      .def(py::init([](double alpha, double thickness, std::array<double, 3> albedo, std::array<double, 3> f0) {
             return ModifiedLayer{alpha, thickness, rgb(albedo), rgb(f0)};
           }),
           py::arg("alpha"), py::arg("thickness"), py::arg("albedo"), py::arg("f0"));

  py::class_<MultipleScatteringLobes>(
      m, "MultipleScatteringLobes",
      "Parameters of SpongeCake's two added lobes (Sec. 5): one ModifiedLayer per layer, weights w1\n"
      "(modified single scattering) and w2 (Lambertian), and the Lambertian lobe's split:\n"
      "split_reflection / pi on the side of wi, split_transmission / pi on the other side.")
      .def(py::init([](std::vector<ModifiedLayer> layers, double w1, double w2, double r, double t) {
             return MultipleScatteringLobes{std::move(layers), w1, w2, {r, t}};
           }),
           py::arg("layers"), py::arg("w1"), py::arg("w2"), py::arg("split_reflection") = 1.0,
           py::arg("split_transmission") = 1.0);

  m.def("flake_stack", [](const std::vector<FlakeLayer>& layers, int channel) {
          if (channel < 0 || channel > 2) throw ConfigError("<python>", "channel", "must be 0, 1 or 2");
          return checked([&] { return sggx::flake_stack(layers, channel); });
        }, py::arg("layers"), py::arg("channel"),
        "One channel of a FlakeLayer stack as Layers (for spongecake_ss_brdf / _btdf).");
  m.def("spongecake_ms_bsdf", [](const std::vector<FlakeLayer>& layers, const MultipleScatteringLobes& lobes,
                                  int channel, py::object ti, py::object pi_, py::object to, py::object po) {
          checked([&] { sggx::multiple_scattering_bsdf(layers, lobes, channel, {0, 0, 1}, {0, 0, 1}); return 0; });
          return vectorized([&](double ti, double pi_, double to, double po) {
            return sggx::multiple_scattering_bsdf(layers, lobes, channel, spherical_direction(ti, pi_),
                                                  spherical_direction(to, po));
          }, ti, pi_, to, po);
        }, py::arg("layers"), py::arg("lobes"), py::arg("channel"), py::arg("theta_i"), py::arg("phi_i"),
        py::arg("theta_o"), py::arg("phi_o"),
        "SpongeCake Sec. 5: W1 f_ss'(wi, wo) + W2 f_lambert(wi, wo), one channel; theta_o > pi/2 is\n"
        "transmission. f_ss' is Eq. 8-16 for the layers with alpha, T, gamma, f0 from `lobes`.");
}

}  // namespace mcref::python
