#include "sim/dataset/entry_assembler.h"

#include <hdf5.h>

namespace mcref {

namespace {

// HDF5 built thread-safe (Debian's is) serialises its calls under a lock of
// its own, so this thread may write OUTPUT while rank 0's computing thread
// writes its parts. Otherwise the assembly waits for the computation.
bool hdf5_threadsafe() {
  hbool_t ts = false;
  return H5is_library_threadsafe(&ts) >= 0 && ts;
}

}  // namespace

EntryAssembler::EntryAssembler(const std::string& output, const DatasetHeader& header,
                               std::vector<std::int64_t> indices,
                               std::function<std::string(std::int64_t)> part_path,
                               const std::vector<bool>& finished)
    : output_(output),
      header_(header),
      indices_(std::move(indices)),
      part_path_(std::move(part_path)),
      finished_(finished) {
  if (hdf5_threadsafe()) thread_ = std::thread([this] { run(); });
}

EntryAssembler::~EntryAssembler() {
  {
    const std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  ready_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void EntryAssembler::run() {
  try {
    DatasetWriter w(output_, header_);
    for (std::size_t k = 0; k < indices_.size(); ++k) {
      {
        std::unique_lock<std::mutex> lock(mu_);
        ready_.wait(lock, [&] { return stop_ || finished_[k]; });
        if (stop_) return;  // the job failed: the writer removes its temporary
      }
      w.add(DatasetReader(part_path_(indices_[k])).entry(indices_[k]));
    }
    w.commit();
  } catch (...) {
    const std::lock_guard<std::mutex> lock(mu_);
    error_ = std::current_exception();
  }
}

void EntryAssembler::finished(std::size_t k) {
  {
    const std::lock_guard<std::mutex> lock(mu_);
    if (error_) std::rethrow_exception(error_);
    finished_[k] = true;
  }
  ready_.notify_all();
}

void EntryAssembler::commit() {
  if (thread_.joinable()) thread_.join();
  else run();
  if (error_) std::rethrow_exception(error_);
}

}  // namespace mcref
