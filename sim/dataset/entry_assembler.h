#pragma once
// Rank 0's assembly of a dataset's OUTPUT from its per-entry parts, beside
// the computation: a thread of its own appends each finished part to OUTPUT
// in index order as soon as it and every entry before it are finished, while
// the entries after it are still being computed. Only the order of the
// writes fixes the bytes, so OUTPUT is the same whenever the entries finish.
// The parts stay until OUTPUT is committed (a killed job resumes from them);
// an unfinished assembly leaves only its temporary file, which the next run
// writing OUTPUT removes. With an HDF5 library not built thread-safe, the
// assembly runs in commit(), after the computation.
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sim/dataset/dataset_file.h"

namespace mcref {

class EntryAssembler {
 public:
  // Writes the entries `indices` (increasing) to `output` with `header`,
  // reading entry i from part_path(i). Those in `finished` are ready now.
  EntryAssembler(const std::string& output, const DatasetHeader& header, std::vector<std::int64_t> indices,
                 std::function<std::string(std::int64_t)> part_path, const std::vector<bool>& finished);
  ~EntryAssembler();  // stops the thread; OUTPUT is not written unless commit() returned
  EntryAssembler(const EntryAssembler&) = delete;
  EntryAssembler& operator=(const EntryAssembler&) = delete;

  // The k-th of `indices` is finished (its part is written). Rethrows the
  // assembly's error, if any, on the caller's thread.
  void finished(std::size_t k);
  // Waits until OUTPUT is committed, once every entry is finished (the
  // thread commits it after the last one), and rethrows its error.
  void commit();

 private:
  void run();

  std::string output_;
  DatasetHeader header_;
  std::vector<std::int64_t> indices_;
  std::function<std::string(std::int64_t)> part_path_;
  std::mutex mu_;
  std::condition_variable ready_;
  std::vector<bool> finished_;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace mcref
