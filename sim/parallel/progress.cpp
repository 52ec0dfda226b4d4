#include "sim/parallel/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "sim/parallel/communicator.h"

namespace mcref {

bool Progress::interactive(bool quiet) {
  const char* ci = std::getenv("CI");
  return !quiet && !(ci && *ci) && (MpiSession::active() || isatty(STDERR_FILENO));
}

Progress::Progress(std::string label, double total_work, bool quiet)
    : label_(std::move(label)), total_(total_work), enabled_(interactive(quiet)), log_(MpiSession::active()),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::advance(double work) {
  if (stop_ && stop_->load(std::memory_order_relaxed)) throw Cancelled();
  done_ += work;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < (log_ ? std::chrono::milliseconds(60000) : std::chrono::milliseconds(200)) &&
      (done_ < total_ || log_))
    return;
  last_draw_ = now;
  const double t = elapsed_seconds();
  const double frac = total_ > 0 ? done_ / total_ : 1;
  const double eta = frac > 0 ? t * (1 - frac) / frac : 0;
  std::fprintf(stderr, log_ ? "%s %5.1f%%  elapsed %02d:%02d  ETA %02d:%02d\n" : "\r%s %5.1f%%  elapsed %02d:%02d  ETA %02d:%02d  ",
               label_.c_str(), 100 * frac, static_cast<int>(t) / 60, static_cast<int>(t) % 60, static_cast<int>(eta) / 60,
               static_cast<int>(eta) % 60);
  std::fflush(stderr);
}

void Progress::finish() {
  if (enabled_ && !log_) std::fprintf(stderr, "\r\033[K");
}

}  // namespace mcref
