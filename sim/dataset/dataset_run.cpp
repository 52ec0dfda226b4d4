#include "sim/dataset/dataset_run.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "sim/dataset/dataset_entry.h"
#include "sim/dataset/entry_assembler.h"
#include "sim/dataset/entry_scheduler.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/simulate.h"
#include "sim/experiment/table_plan.h"
#include "sim/files/directory_lock.h"
#include "sim/hdf5/table_file.h"
#include "sim/parallel/progress.h"

namespace mcref {

namespace {

namespace fs = std::filesystem;

std::string part_path(const std::string& dir, std::int64_t index) {
  return dir + "/entry-" + std::to_string(index) + ".h5";
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += (s.empty() ? "" : "\n") + l;
  return s;
}

// The tables the dataset asks for, in its order (all if none named; the
// names were checked up front).
std::vector<Table> select_tables(const DatasetConfig& c, std::vector<Table> tables) {
  if (c.tables.empty()) return tables;
  std::vector<Table> kept;
  for (const std::string& name : c.tables) {
    auto it = std::find_if(tables.begin(), tables.end(), [&](const Table& t) { return t.name == name; });
    if (it == tables.end()) throw std::logic_error("table " + name + " was not simulated");
    kept.push_back(std::move(*it));
  }
  return kept;
}

// A finished part of this dataset holding `index`, or false if absent or
// damaged (then it is recomputed). A part of another dataset is an error, and
// so is anything there but a file (a FIFO would block the read forever), a
// file this process cannot read (a collaborator's part, kept) and one of
// another format version (another mcref's).
bool usable_part(const std::string& path, const DatasetHeader& expect, std::int64_t index, const std::string& dir) {
  if (!fs::exists(path)) return false;
  if (!fs::is_regular_file(path))
    throw ConfigError(path, "", "is not a regular file, and a part of the dataset must be one; remove it");
  if (!std::ifstream(path, std::ios::binary))
    throw ConfigError(path, "", "cannot be read (permissions?): a part of the dataset is neither reused nor replaced unread");
  std::unique_ptr<DatasetReader> r;
  try {
    r = std::make_unique<DatasetReader>(path);
  } catch (const ConfigError& e) {
    if (std::string(e.what()).find("key 'format_version'") != std::string::npos) throw;
    std::fprintf(stderr, "mcref dataset: warning: recomputing a damaged part (%s)\n", e.what());
    fs::remove(path);
    return false;
  }
  const std::string why = expect.difference(r->header());
  if (!why.empty())
    throw ConfigError(dir, "", "holds entries of another dataset (" + why + "); remove it or choose another -o");
  if (r->indices() != std::vector<std::int64_t>{index}) {
    fs::remove(path);
    return false;
  }
  return true;
}

// Removes this shard's parts once OUTPUT holds them, the temporary files of
// interrupted part writes, and the directory if that leaves it empty.
// (This shard's entries: shard + k shards, k < entries.)
void remove_parts(const std::string& dir, std::int64_t shard, std::int64_t shards, std::int64_t entries) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  for (std::int64_t k = 0; k < entries; ++k) fs::remove(part_path(dir, shard + k * shards), ec);
  for (const auto& f : fs::directory_iterator(dir, ec))
    if (f.path().filename().string().rfind("entry-", 0) == 0 && f.path().filename().string().find(".h5.tmp.") != std::string::npos)
      fs::remove(f.path(), ec);
  fs::remove(dir, ec);  // only if empty: anything else stays
}

}  // namespace

DatasetHeader dataset_header(const DatasetConfig& c, const std::string& shard) {
  DatasetHeader h;
  h.mcref_version = mcref_version();
  h.git_commit = mcref_git_commit();
  h.sim_fingerprint = mcref_sim_fingerprint();
  h.seed = c.seed;
  h.entries = c.entries();
  h.shard = shard;
  h.compression = c.compression;
  h.dataset_config = c.text;
  h.experiment_config = c.experiment_text;
  h.experiment_file = c.experiment;
  h.columns = c.column_names();
  for (const DatasetParameter& p : c.parameters)
    if (p.categorical()) h.labels[p.column_names()[0]] = p.labels;
  return h;
}

DatasetRunSummary run_dataset(const DatasetConfig& c, const DatasetRunOptions& o) {
  DatasetRunSummary s;
  const std::string shard = o.shards == 1 ? "all" : std::to_string(o.shard) + "/" + std::to_string(o.shards);
  DatasetHeader final_header = dataset_header(c, shard);
  final_header.lean = o.lean;
  DatasetHeader part_header = dataset_header(c, "part");
  part_header.sums = true;  // the sums alone: half the bytes to write, keep and read back
  // This shard's entries are index(k) = shard + k shards, k < s.entries; each
  // is planned from its index when needed, so nothing scales with the
  // declared size but the entries a run computes.
  s.entries = c.entries() > o.shard ? (c.entries() - o.shard - 1) / o.shards + 1 : 0;
  auto index = [&](std::int64_t k) { return o.shard + k * o.shards; };
  const Communicator& ranks = *o.ranks;
  // An existing OUTPUT holding this shard: nothing to do; anything else is an
  // error. Rank 0 alone looks (only it writes OUTPUT) and tells the others.
  std::string up_to_date;
  check_on_root(ranks, [&] {
    if (!fs::exists(o.output)) return;
    std::string why;
    try {
      DatasetReader r(o.output);
      why = final_header.difference(r.header());
      if (why.empty() && r.header().shard != shard) why = "it is shard " + r.header().shard + ", not " + shard;
      if (why.empty() && static_cast<std::int64_t>(r.indices().size()) != s.entries) why = "it is incomplete";
    } catch (const ConfigError& e) {
      why = "it is not a readable mcref dataset";
    }
    if (!why.empty()) throw ConfigError(o.output, "", "exists and " + why + "; remove it or choose another -o");
    up_to_date = "yes";
    // Parts left by a run stopped after OUTPUT was committed (while it removed them).
    if (fs::is_directory(o.output + ".parts")) {
      const DirectoryLock lock(o.output + ".parts", o.output, "-o");
      remove_parts(o.output + ".parts", o.shard, o.shards, s.entries);
    }
  });
  ranks.broadcast(up_to_date);
  if (!up_to_date.empty()) {
    s.complete = s.up_to_date = true;
    return s;
  }
  const std::string dir = o.output + ".parts";
  // Rank 0 alone checks every value of the parameters, scans the parts in index
  // order (it removes damaged ones) up to the entries this run computes (all,
  // or the first --stop-after ones), and validates each of those before
  // anything is simulated or written; the other ranks learn whether that failed.
  std::vector<std::int64_t> pending;
  bool more = false;  // pending entries beyond --stop-after
  std::vector<bool> finished;  // of this shard's entries, k < s.entries (on rank 0)
  std::string error;
  std::unique_ptr<DirectoryLock> lock;  // held by rank 0 to the end: one process per OUTPUT
  if (ranks.root()) {
    try {
      check_parameter_values(c);
      lock = std::make_unique<DirectoryLock>(dir, o.output, "-o");
      for (std::int64_t k = 0; k < s.entries && !more; ++k) {
        finished.push_back(usable_part(part_path(dir, index(k)), part_header, index(k), dir));
        if (finished.back()) ++s.reused;
        else if (o.stop_after < 0 || static_cast<std::int64_t>(pending.size()) < o.stop_after) pending.push_back(index(k));
        else more = true;
      }
      for (std::int64_t i : pending) {
        const Experiment ex = entry_experiment(c, plan_entry(c, i));
        check_memory(ex, o.threads);
        check_table_names(ex, c.tables, c.file, "dataset.tables");
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  agree_on_error(ranks, error);
  Progress progress("dataset", static_cast<double>(pending.size()), o.quiet || !ranks.root());
  SimulateOptions sim;
  sim.threads = o.threads;
  sim.quiet = true;
  sim.tables = c.tables;  // the others are not computed where they can be left out
  auto compute = [&](std::int64_t i) {
    const EntryPlan p = plan_entry(c, i);
    const Experiment ex = entry_experiment(c, p);
    SimulateSummary summary;
    DatasetEntry e;
    e.index = p.index;
    e.seed = p.seed;
    e.parameters = p.columns;
    e.assignments = join_lines(p.assignments);
    e.config = ex.text;
    e.tables = select_tables(c, mcref::simulate(ex, sim, &summary));
    fs::create_directories(dir);
    DatasetWriter w(part_path(dir, p.index), part_header);
    w.add(e);
    w.commit();
    return summary.rays;
  };
  // Rank 0 assembles OUTPUT while the entries are computed, unless this run
  // stops before the last one.
  std::unique_ptr<EntryAssembler> assembler;
  if (ranks.root() && !more) {
    std::vector<std::int64_t> indices;
    for (std::int64_t k = 0; k < s.entries; ++k) indices.push_back(index(k));
    assembler = std::make_unique<EntryAssembler>(o.output, final_header, std::move(indices),
                                                 [&](std::int64_t i) { return part_path(dir, i); }, finished);
  }
  const ScheduleSummary done = schedule_entries(ranks, pending, -1, compute, [&](std::int64_t i, double) {
    progress.advance(1);
    if (assembler) assembler->finished(static_cast<std::size_t>((i - o.shard) / o.shards));
  });
  s.computed = done.computed;
  s.rays = done.rays;
  progress.finish();
  s.seconds = progress.elapsed_seconds();
  if (!assembler) return s;
  assembler->commit();
  remove_parts(dir, o.shard, o.shards, s.entries);
  s.complete = true;
  return s;
}

std::int64_t merge_datasets(const std::vector<std::string>& inputs, const std::string& output, bool quiet, bool lean) {
  if (inputs.empty()) throw ConfigError("command line", "", "mcref merge needs at least one shard file");
  std::vector<std::unique_ptr<DatasetReader>> shards;
  for (const std::string& in : inputs) {
    shards.push_back(std::make_unique<DatasetReader>(in));
    if (shards.back()->header().lean)
      throw ConfigError(in, "storage", "is a lean dataset (float32 value and stderr, no sums) and cannot be merged; merge the full shards (merge --lean writes a lean result)");
  }
  const DatasetHeader& first = shards[0]->header();
  for (std::size_t k = 1; k < shards.size(); ++k) {
    const std::string why = first.difference(shards[k]->header());
    if (!why.empty()) throw ConfigError(inputs[k], "", "does not belong with " + inputs[0] + ": " + why);
  }
  const std::int64_t n = first.entries;
  // (entry, shard) pairs, sorted: memory as the entries the files hold, not
  // as the declared count (a part of a 2^40-entry dataset was a bad_alloc).
  std::vector<std::pair<std::int64_t, std::size_t>> owner;
  for (std::size_t k = 0; k < shards.size(); ++k)
    for (std::int64_t i : shards[k]->indices()) {
      if (i < 0 || i >= n) throw ConfigError(inputs[k], "", "holds entry " + std::to_string(i) + " outside [0, " + std::to_string(n) + ")");
      owner.emplace_back(i, k);
    }
  std::sort(owner.begin(), owner.end());
  for (std::size_t j = 1; j < owner.size(); ++j)
    if (owner[j].first == owner[j - 1].first)
      throw ConfigError(inputs[owner[j].second], "", "overlaps with " + inputs[owner[j - 1].second] + ": both hold entry " +
                                                       std::to_string(owner[j].first) + " (each shard K/N must be given once)");
  if (static_cast<std::int64_t>(owner.size()) != n) {
    std::vector<std::int64_t> first_missing;  // the first 9 (8 are listed)
    for (std::int64_t i = 0, j = 0; i < n && first_missing.size() < 9; ++i)
      if (j < static_cast<std::int64_t>(owner.size()) && owner[static_cast<std::size_t>(j)].first == i) ++j;
      else first_missing.push_back(i);
    std::string list;
    for (std::size_t j = 0; j < std::min<std::size_t>(first_missing.size(), 8); ++j)
      list += (j ? ", " : "") + std::to_string(first_missing[j]);
    if (first_missing.size() > 8) list += ", ...";
    throw ConfigError(output, "", std::to_string(n - static_cast<std::int64_t>(owner.size())) + " of " + std::to_string(n) +
                                      " entries are missing from the shards given (entries " + list +
                                      "); merge every shard K/N, K = 0..N-1");
  }
  DatasetHeader h = first;
  h.shard = "all";
  h.mcref_version = mcref_version();  // of the build that writes the file, as after a resume: shards agree on the rest
  h.git_commit = mcref_git_commit();
  h.lean = lean;
  h.sums = false;  // (parts given as shards hold sums only; the result is full or lean)
  Progress progress("merge", static_cast<double>(n), quiet);
  DatasetWriter w(output, h);
  for (std::int64_t i = 0; i < n; ++i) {
    w.add(shards[owner[static_cast<std::size_t>(i)].second]->entry(i));
    progress.advance(1);
  }
  w.commit();
  progress.finish();
  return n;
}

}  // namespace mcref
