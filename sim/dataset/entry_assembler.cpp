#include "sim/dataset/entry_assembler.h"

namespace mcref {

EntryAssembler::EntryAssembler(const std::string& output, const DatasetHeader& header,
                               std::vector<std::int64_t> indices,
                               std::function<std::string(std::int64_t)> part_path,
                               const std::vector<bool>& finished)
    : output_(output),
      header_(header),
      indices_(std::move(indices)),
      part_path_(std::move(part_path)),
      finished_(finished),
      thread_([this] { run(); }) {}

EntryAssembler::~EntryAssembler() {
  {
    const std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  ready_.notify_all();
  if (thread_.joinable()) thread_.join();
}

// HDF5 (built thread-safe) is called from this thread alone for OUTPUT; the
// computing thread of rank 0 writes its parts meanwhile, under HDF5's lock.
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
  thread_.join();
  if (error_) std::rethrow_exception(error_);
}

}  // namespace mcref
