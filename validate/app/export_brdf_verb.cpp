// mcref export-brdf TABLES.h5 --table NAME --format merl -o OUT.binary
#include <cstdio>

#include "sim/experiment/config_error.h"
#include "sim/files/merl_file.h"
#include "sim/files/output_path.h"
#include "sim/hdf5/table_file.h"
#include "sim/tally/brdf_interpolation.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

namespace {
const char* kHelp =
    "usage: mcref export-brdf TABLES.h5 --table NAME --format merl -o OUT.binary [--quiet]\n"
    "\n"
    "Writes an isotropic BRDF table (quantity brdf) as a MERL binary file, read by\n"
    "the MERL database's BRDFRead.cpp, pbrt-v2's measured material, Disney's BRDF\n"
    "Explorer and most BRDF-fitting tools (only BRDFRead.cpp's layout is tested):\n"
    "  header: three int32 90 90 180 (theta_h, theta_d, phi_d);\n"
    "  data:   3 x 90 x 90 x 180 doubles, channel-major (R, G, B), each value the\n"
    "          BRDF divided by MERL's scale 1/1500, 1.15/1500, 1.66/1500 (the reader\n"
    "          multiplies by it); little-endian.\n"
    "Conventions: values are f_r in 1/sr WITHOUT the cosine factor (as mcref's tables\n"
    "and as BRDFRead.cpp returns them; renderers multiply by cos theta_i). Grid angles:\n"
    "theta_h = (i/90)^2 90 deg, theta_d = j/2 deg, phi_d = k deg. Cells with a\n"
    "direction below the horizon hold 0. A grey table is written to all three channels.\n"
    "Values at the grid's directions are interpolated trilinearly in (theta_i, theta_o,\n"
    "phi) between the table's bin averages (at the theta_i points and the theta_o and\n"
    "phi bin centres), held constant beyond the outermost points. Density rule: theta_i\n"
    "from <= 5 deg to >= 75 deg in steps <= 15 deg, >= 8 theta_o bins, >= 8 phi bins\n"
    "over [0, pi]; coarser tables are refused, and so are anisotropic tables (phi over\n"
    "[0, 2 pi) or several phi_i: MERL is isotropic). Delta lobes (a smooth mirror, the\n"
    "unscattered light; table <name>_delta) cannot be held: a warning gives the largest\n"
    "energy they carry, and the file leaves them out.\n";
// Warns (whatever --quiet says: the output lacks energy) if the exported
// table's delta lobes (a smooth mirror, the unscattered light) carry energy,
// which a MERL file cannot hold: their table <base>_delta (brdf_tally.cpp),
// the exported table's component, largest over theta_i and channels; and
// that it could not check when the file lacks that table.
void warn_of_delta_lobes(const TableFile& file, const Table& t, const std::string& output) {
  const auto part = t.attributes.find("component");
  if (part == t.attributes.end()) return;
  const std::string suffix = part->second == "total" ? "" : "_" + part->second;
  const std::string base = t.name.substr(0, t.name.size() - suffix.size());
  const Table* delta = file.find(base + "_delta");
  if (!delta || delta->axes.size() != 4) {
    if (t.attributes.count("delta_lobes"))
      std::fprintf(stderr,
                   "mcref export-brdf: warning: %s: the file has no table %s_delta, so whether delta lobes (a smooth "
                   "mirror or unscattered light) carry energy that %s leaves out cannot be checked\n",
                   t.name.c_str(), base.c_str(), output.c_str());
    return;
  }
  const std::vector<double> v = delta->values();
  const std::size_t comps = delta->axes[2].size(), channels = delta->axes[3].size(), per_ti = v.size() / delta->axes[0].size();
  // The component's index among the delta table's (its attribute "components": names, then the total last).
  std::size_t comp = comps - 1;
  const auto names = delta->attributes.find("components");
  if (part->second != "total" && names != delta->attributes.end()) {
    std::size_t k = 0, from = 0;
    for (std::size_t to; (to = names->second.find(',', from)) != std::string::npos; from = to + 1, ++k)
      if (names->second.compare(from, to - from, part->second) == 0) comp = k;
  }
  double largest = 0;
  std::size_t at = 0;
  for (std::size_t n = 0; n < v.size(); ++n)
    if ((n / channels) % comps == comp && v[n] > largest) largest = v[n], at = n / per_ti;
  if (!(largest > 0)) return;
  std::fprintf(stderr,
               "mcref export-brdf: warning: %s: delta lobes (a smooth mirror or unscattered light) carry up to %.3g of the "
               "incident energy (theta_i = %.4g deg); a MERL file cannot hold them, and %s leaves them out\n",
               delta->name.c_str(), largest, delta->axes[0].centre(at) * 180 / kPi, output.c_str());
}

}  // namespace

int export_brdf(const std::vector<std::string>& raw) {
  std::vector<std::string> rest;
  std::string table, format;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] == "--table" || raw[i] == "--format") {
      if (i + 1 >= raw.size()) throw ConfigError("command line", raw[i], "needs a value");
      if (raw[i + 1].rfind("--", 0) == 0)  // (--table --format merl took "--format" as the table)
        throw ConfigError("command line", raw[i], "needs a value, and " + raw[i + 1] + " is an option");
      given_once(seen, raw[i], raw[i]);
      (raw[i] == "--table" ? table : format) = raw[i + 1];
      ++i;
    } else {
      rest.push_back(raw[i]);
    }
  }
  Args a = parse_args(rest, "export-brdf", false);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref export-brdf needs exactly one TABLES.h5 (see --help)");
  if (table.empty()) throw ConfigError("command line", "--table", "the table to export is required (--table NAME)");
  if (format.empty()) throw ConfigError("command line", "--format", "the output format is required (--format merl)");
  if (format != "merl") throw ConfigError("command line", "--format", "\"" + format + "\" is not a known format (allowed: merl)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output file is required (-o OUT.binary)");
  check_output_file(a.output, {a.positional[0]});
  const TableFile file = read_table_file(a.positional[0]);
  const Table* t = file.find(table);
  if (!t) throw ConfigError(a.positional[0], "--table", "no table '" + table + "' in the file (see mcref info)");
  const BrdfInterpolation f(*t, a.positional[0]);
  std::array<std::vector<double>, 3> rgb;
  for (auto& c : rgb) c.resize(kMerlCells);
  std::size_t n = 0;
  for (int i = 0; i < kMerlThetaH; ++i)
    for (int j = 0; j < kMerlThetaD; ++j)
      for (int k = 0; k < kMerlPhiD; ++k, ++n) {
        Vec3 wi, wo;
        merl_directions(i, j, k, wi, wo);
        const double ti = std::acos(std::fmax(-1.0, std::fmin(1.0, wi.z))), to = std::acos(std::fmax(-1.0, std::fmin(1.0, wo.z)));
        const double phi = std::atan2(wo.y, wo.x) - std::atan2(wi.y, wi.x);
        for (int c = 0; c < 3; ++c) rgb[c][n] = f(ti, to, phi, c);
      }
  write_merl_file(a.output, rgb);
  warn_of_delta_lobes(file, *t, a.output);
  if (!a.quiet) std::fprintf(stderr, "mcref export-brdf: %s/%s -> %s (MERL, 90 x 90 x 180 x 3)\n", a.positional[0].c_str(), table.c_str(), a.output.c_str());
  return 0;
}

}  // namespace mcref::cli
