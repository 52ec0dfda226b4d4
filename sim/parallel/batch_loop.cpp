#include "sim/parallel/batch_loop.h"

#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>

namespace mcref {

namespace {

constexpr int kBatchTag = 17;

// A batch's tallies as bytes: per table, batches, sum, sum_sq, attributes.
class Bytes {
 public:
  void put(const void* p, std::size_t n) { s_.append(static_cast<const char*>(p), n); }
  void put_size(std::uint64_t n) { put(&n, sizeof n); }
  void put_doubles(const std::vector<double>& v) {
    put_size(v.size());
    put(v.data(), v.size() * sizeof(double));
  }
  void put_string(const std::string& t) {
    put_size(t.size());
    put(t.data(), t.size());
  }
  std::string& str() { return s_; }

 private:
  std::string s_;
};

class Reader {
 public:
  explicit Reader(const std::string& s) : s_(s) {}
  void get(void* p, std::size_t n) {
    if (at_ + n > s_.size()) throw std::runtime_error("a batch message from another rank is truncated");
    std::memcpy(p, s_.data() + at_, n);
    at_ += n;
  }
  std::uint64_t get_size() {
    std::uint64_t n = 0;
    get(&n, sizeof n);
    return n;
  }
  void get_doubles(std::vector<double>& v) {
    if (get_size() != v.size()) throw std::runtime_error("a batch message from another rank has the wrong table size");
    get(v.data(), v.size() * sizeof(double));
  }
  std::string get_string() {
    std::string t(get_size(), '\0');
    get(t.data(), t.size());
    return t;
  }

 private:
  const std::string& s_;
  std::size_t at_ = 0;
};

std::string to_bytes(const BatchLoop::Tables& tables) {
  Bytes b;
  for (const auto& group : tables)
    for (const Table& t : group) {
      b.put_size(static_cast<std::uint64_t>(t.batches));
      b.put_doubles(t.sum);
      b.put_doubles(t.sum_sq);
      b.put_size(t.attributes.size());
      for (const auto& [key, text] : t.attributes) {
        b.put_string(key);
        b.put_string(text);
      }
    }
  return std::move(b.str());
}

void from_bytes(const std::string& bytes, BatchLoop::Tables& tables) {
  Reader r(bytes);
  for (auto& group : tables)
    for (Table& t : group) {
      t.batches = static_cast<std::int64_t>(r.get_size());
      r.get_doubles(t.sum);
      r.get_doubles(t.sum_sq);
      t.attributes.clear();
      for (std::uint64_t n = r.get_size(); n > 0; --n) {
        std::string key = r.get_string();
        t.attributes[key] = r.get_string();
      }
    }
}

void merge_into(BatchLoop::Tables& tables, const BatchLoop::Tables& one) {
  for (std::size_t k = 0; k < tables.size(); ++k)
    for (std::size_t i = 0; i < tables[k].size(); ++i) tables[k][i].merge(one[k][i]);
}

}  // namespace

void BatchLoop::run(int count, Tables& tables, const Batch& batch) const {
  if (ranks_.size() == 1 && !keep_batch_values_) {
    for (int b = 0; b < count; ++b) batch(b, tables);
    return;
  }
  std::optional<DistributedStep> step;
  if (ranks_.size() > 1) step.emplace();
  const Tables empty = tables;
  if (keep_batch_values_ && ranks_.root())
    for (auto& group : tables)
      for (Table& t : group) t.keep_batch_values = t.batches == 0;
  if (ranks_.size() == 1) {
    for (int b = 0; b < count; ++b) {
      Tables one = empty;
      batch(b, one);
      merge_into(tables, one);
    }
    return;
  }
  const int n = ranks_.size();
  for (int b = 0; b < count; ++b) {
    const int owner = b % n;
    if (ranks_.root()) {
      Tables one = empty;
      if (owner == 0) {
        batch(b, one);
      } else {
        from_bytes(ranks_.receive(owner, kBatchTag), one);
        progress_.advance(batch_work_);
      }
      merge_into(tables, one);
    } else if (owner == ranks_.rank()) {
      Tables one = empty;
      batch(b, one);
      ranks_.send(0, kBatchTag, to_bytes(one));
    }
  }
}

}  // namespace mcref
