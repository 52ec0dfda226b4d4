#include "sim/dataset/entry_scheduler.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace mcref {

namespace {

constexpr int kAskTag = 31;    // worker -> rank 0: {finished entry or -1, its rays}
constexpr int kEntryTag = 32;  // rank 0 -> worker: {next entry or -1 = stop}

struct Message {
  std::int64_t index = -1;
  double rays = 0;
};

std::string encode(const Message& m) {
  std::string s(sizeof m, '\0');
  std::memcpy(s.data(), &m, sizeof m);
  return s;
}

Message decode(const std::string& s) {
  if (s.size() != sizeof(Message)) throw std::runtime_error("a scheduler message from another rank is malformed");
  Message m;
  std::memcpy(&m, s.data(), sizeof m);
  return m;
}

ScheduleSummary serve(const Communicator& ranks, const std::vector<std::int64_t>& queue, std::size_t count,
                      const std::function<double(std::int64_t)>& compute,
                      const std::function<void(std::int64_t, double)>& done) {
  ScheduleSummary s;
  std::mutex mu;
  std::size_t next = 0;
  std::vector<Message> finished;  // by rank 0's own thread, not yet reported
  std::exception_ptr error;
  std::atomic<bool> idle{false};
  auto take = [&]() -> std::int64_t {
    const std::lock_guard<std::mutex> lock(mu);
    return next < count ? queue[next++] : -1;
  };
  std::thread own([&] {
    try {
      for (std::int64_t i; (i = take()) >= 0;) {
        const double rays = compute(i);
        const std::lock_guard<std::mutex> lock(mu);
        finished.push_back({i, rays});
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(mu);
      error = std::current_exception();
    }
    idle = true;
  });
  auto report = [&](const Message& m) {
    ++s.computed;
    s.rays += m.rays;
    done(m.index, m.rays);
  };
  try {
    int asking = ranks.size() - 1;  // workers not yet told to stop
    while (asking > 0 || !idle) {
      bool busy = false;
      if (asking > 0 && ranks.pending(Communicator::kAnyRank, kAskTag)) {
        int from = 0;
        const Message m = decode(ranks.receive(Communicator::kAnyRank, kAskTag, &from));
        if (m.index >= 0) report(m);
        const std::int64_t i = take();
        ranks.send(from, kEntryTag, encode({i, 0}));
        if (i < 0) --asking;
        busy = true;
      }
      std::vector<Message> mine;
      {
        const std::lock_guard<std::mutex> lock(mu);
        if (error) std::rethrow_exception(error);
        mine.swap(finished);
      }
      for (const Message& m : mine) report(m);
      if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  } catch (...) {
    own.detach();  // the job ends (see main); the thread need not finish its entry
    throw;
  }
  own.join();
  if (error) std::rethrow_exception(error);
  for (const Message& m : finished) report(m);
  return s;
}

ScheduleSummary work(const Communicator& ranks, const std::function<double(std::int64_t)>& compute) {
  ScheduleSummary s;
  Message m;
  for (;;) {
    ranks.send(0, kAskTag, encode(m));
    const std::int64_t i = decode(ranks.receive(0, kEntryTag)).index;
    if (i < 0) return s;
    m = {i, compute(i)};
    ++s.computed;
    s.rays += m.rays;
  }
}

}  // namespace

ScheduleSummary schedule_entries(const Communicator& ranks, const std::vector<std::int64_t>& queue,
                                 std::int64_t limit, const std::function<double(std::int64_t)>& compute,
                                 const std::function<void(std::int64_t, double)>& done) {
  const std::size_t count =
      limit < 0 ? queue.size() : std::min(queue.size(), static_cast<std::size_t>(limit));
  if (ranks.size() == 1) {
    ScheduleSummary s;
    for (std::size_t k = 0; k < count; ++k) {
      const double rays = compute(queue[k]);
      ++s.computed;
      s.rays += rays;
      done(queue[k], rays);
    }
    return s;
  }
  const DistributedStep step;
  return ranks.root() ? serve(ranks, queue, count, compute, done) : work(ranks, compute);
}

}  // namespace mcref
