#include "validate/suite_outputs.h"

#include <filesystem>
#include <system_error>

#include "sim/files/output_path.h"

namespace mcref {

namespace fs = std::filesystem;

void check_suite_outputs(const Suite& suite, const std::vector<Experiment>& experiments, const std::string& out_dir) {
  std::vector<std::string> inputs = suite.files;
  for (const Case& c : suite.cases) inputs.push_back(c.experiment_path);
  for (const Experiment& ex : experiments)
    for (const InputFile& f : ex.inputs) inputs.push_back(f.path);
  const fs::path out(out_dir), tables = out / "tables";
  check_output_directory(out_dir, inputs);
  std::error_code ec;
  if (fs::exists(out, ec)) check_output_directory(tables.string(), inputs);  // else created with OUTDIR
  check_replaceable_file((out / "results.json").string(), inputs);
  check_inputs_outside(tables.string(), inputs, "mcref validate -o " + out_dir);
  for (const Case& c : suite.cases) check_replaceable_file((tables / (c.name + ".h5")).string(), inputs);
}

}  // namespace mcref
