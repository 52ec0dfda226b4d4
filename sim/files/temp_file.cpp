#include "sim/files/temp_file.h"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <system_error>


namespace mcref {

namespace fs = std::filesystem;

namespace {

// The temporaries the signal handler removes. A signal handler can only reach
// process-wide state, so this list is the one global of mcref: fixed slots of
// plain characters, claimed and released under a mutex, read (never written)
// by the handler.
constexpr int kSlots = 64;
constexpr std::size_t kPathMax = 4096;
struct Slot {
  std::atomic<bool> used{false};
  char path[kPathMax];
};
std::array<Slot, kSlots> g_slots;
std::mutex g_slots_mutex;
std::once_flag g_handlers_installed;
std::atomic<bool> g_signals_to_host{false};

extern "C" void remove_temps_and_reraise(int sig) {
  for (Slot& s : g_slots)
    if (s.used.load(std::memory_order_acquire)) unlink(s.path);
  signal(sig, SIG_DFL);
  raise(sig);
}

void install_handlers() {
  if (g_signals_to_host.load()) return;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    sigaction(sig, nullptr, &old);
    if (old.sa_handler == SIG_IGN) continue;  // e.g. nohup: keep ignoring
    struct sigaction sa {};
    sa.sa_handler = remove_temps_and_reraise;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
  }
}

int claim_slot(const std::string& path) {
  std::call_once(g_handlers_installed, install_handlers);
  if (path.size() >= kPathMax) return -1;
  const std::lock_guard<std::mutex> lock(g_slots_mutex);
  for (int i = 0; i < kSlots; ++i) {
    if (g_slots[i].used.load(std::memory_order_relaxed)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].used.store(true, std::memory_order_release);
    return i;
  }
  return -1;  // more than kSlots at once: still removed on destruction and by the next run
}

void release_slot(int i) {
  if (i < 0) return;
  const std::lock_guard<std::mutex> lock(g_slots_mutex);
  g_slots[i].used.store(false, std::memory_order_release);
}

}  // namespace

void leave_signals_to_host() { g_signals_to_host.store(true); }

bool is_temp_name(const std::string& name, const std::string& output_name) {
  const std::string prefix = output_name + ".tmp.";
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string digits = name.substr(prefix.size());
  return digits.find_first_not_of("0123456789") == std::string::npos && digits.size() <= 9;
}

int remove_stale_temps(const std::string& output) {
  const fs::path out = fs::absolute(output);
  const std::string prefix = out.filename().string() + ".tmp.";
  std::error_code ec;
  int removed = 0;
  for (fs::directory_iterator it(out.parent_path(), ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!is_temp_name(name, out.filename().string())) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name.substr(prefix.size())));
    if (pid == getpid() || kill(pid, 0) == 0 || errno != ESRCH) continue;  // its writer may still run
    std::error_code rm;
    if (fs::remove(it->path(), rm)) ++removed;
  }
  return removed;
}

TempFile::TempFile(std::string output) : output_(std::move(output)) {
  remove_stale_temps(output_);
  tmp_ = output_ + ".tmp." + std::to_string(getpid());
  slot_ = claim_slot(tmp_);
}

TempFile::~TempFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
  release_slot(slot_);
}

void write_text_file(const std::string& path, const std::string& text) {
  TempFile tmp(path);
  {
    std::ofstream out(tmp.path(), std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(path + ": writing failed (disk full?)");
    out.close();
    if (out.fail()) throw std::runtime_error(path + ": closing failed (disk full?)");
  }
  tmp.commit();
}

void TempFile::commit() {
  std::error_code ec;
  fs::rename(tmp_, output_, ec);
  if (ec) throw std::runtime_error(output_ + ": cannot move the finished file into place: " + ec.message());
  committed_ = true;
}

}  // namespace mcref
