#include "hardsphere/atomic_file.hpp"

#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include "hardsphere/errors.hpp"

namespace hardsphere {

namespace {

namespace fs = std::filesystem;

// The temporaries a signal handler must remove, in storage that needs no allocation: a slot's
// path is written while the slot is free and published by `used` (lock-free, so the handler may
// read it). Registration happens before the file is created, removal of the entry after the
// file is gone, so a signal at any moment finds every temporary that exists. A forked child
// inherits the table and the AtomicFiles: `owner` keeps it from removing its parent's files.
constexpr int kSlots = 32;
constexpr std::size_t kSlotPath = 4096 + 64;
struct Slot {
  std::atomic<int> used{0};
  pid_t owner = 0;
  char path[kSlotPath];
};
Slot g_slots[kSlots];
std::mutex g_register_mutex;
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads slot flags");

// Every signal whose default action ends the process and that can be caught: the warnings of
// batch systems (SIGUSR1, SIGUSR2, SIGALRM before a wall-time limit), a closed pipe, abort(),
// and faults, whose handler only unlinks (async-signal-safe) before the default action.
constexpr int kCleanupSignals[] = {SIGHUP,  SIGINT,  SIGQUIT,   SIGILL,  SIGTRAP, SIGABRT, SIGBUS,
                                   SIGFPE,  SIGUSR1, SIGSEGV,   SIGUSR2, SIGPIPE, SIGALRM, SIGTERM,
                                   SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF, SIGPOLL, SIGPWR,  SIGSYS};

int register_temporary(const std::string& tmp, const std::string& shown) {
  if (tmp.size() >= kSlotPath) throw InputError("cannot write '" + shown + "': path is too long");
  std::lock_guard<std::mutex> lock(g_register_mutex);
  int free_slot = -1;
  for (int i = 0; i < kSlots; ++i) {
    if (!g_slots[i].used.load(std::memory_order_acquire)) {
      if (free_slot < 0) free_slot = i;
    } else if (tmp == g_slots[i].path) {
      throw InputError("cannot write '" + shown + "': this run is already writing that file");
    }
  }
  if (free_slot < 0) throw std::runtime_error("more than " + std::to_string(kSlots) + " output files open at once");
  std::memcpy(g_slots[free_slot].path, tmp.c_str(), tmp.size() + 1);
  g_slots[free_slot].owner = ::getpid();
  g_slots[free_slot].used.store(1, std::memory_order_release);
  return free_slot;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slots[slot].used.store(0, std::memory_order_release);
}

extern "C" void remove_temporaries_and_die(int sig) {
  const int saved = errno;
  const pid_t self = ::getpid();
  for (auto& s : g_slots)
    if (s.used.load(std::memory_order_acquire) && s.owner == self) ::unlink(s.path);
  errno = saved;
  // Die by the same signal, so the parent sees "killed by SIGxxx": it is blocked while this
  // handler runs and delivered with the default action as soon as the handler returns.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

// The real-time signals end the process by default too.
template <class F>
void for_each_cleanup_signal(F&& f) {
  for (int s : kCleanupSignals) f(s);
  for (int s = SIGRTMIN; s <= SIGRTMAX; ++s) f(s);
}

sigset_t cleanup_signal_set() {
  sigset_t set;
  sigemptyset(&set);
  for_each_cleanup_signal([&](int s) { sigaddset(&set, s); });
  return set;
}

std::string errno_text(int e) { return e ? std::string(": ") + std::strerror(e) : std::string(); }

// Refuses a target that exists and is not a regular file: renaming over it would replace a
// directory entry such as /dev/null or a FIFO with a plain file.
// `who` names the output in the message, e.g. "--json 'x'".
void check_target(const std::string& target, const std::string& who) {
  std::error_code ec;
  const auto st = fs::status(target, ec);
  if (fs::is_directory(st)) throw InputError(who + " is a directory");
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(who + " exists and is not a regular file (outputs are replaced whole, by renaming)");
}

}  // namespace

std::string resolved_output_path(const std::string& path) {
  if (path.empty()) throw InputError("empty output file name");
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec);
  if (ec) throw InputError("cannot resolve output path '" + path + "': " + ec.message());
  fs::path resolved = fs::weakly_canonical(abs, ec);
  // weakly_canonical leaves a dangling symlink as it is; follow it to the file it will create.
  std::error_code missing;  // symlink_status reports a path that does not exist as an error
  for (int hops = 0; !ec && hops < 40 && fs::is_symlink(fs::symlink_status(resolved, missing)); ++hops) {
    const fs::path link = fs::read_symlink(resolved, ec);
    if (!ec) resolved = fs::weakly_canonical(resolved.parent_path() / link, ec);
  }
  if (ec) throw InputError("cannot resolve output path '" + path + "': " + ec.message());
  return resolved.string();
}

void check_output_paths(const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::map<std::string, std::size_t> seen;  // resolved path -> entry
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const auto& [option, path] = outputs[k];
    if (path.empty()) throw InputError(option + ": empty file name");
    const std::string target = resolved_output_path(path);
    check_target(target, option + " '" + path + "'");
    const fs::path dir = fs::path(target).parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
      throw InputError(option + " '" + path + "': directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw InputError(option + " '" + path + "': cannot create files in '" + dir.string() + "'" + errno_text(errno));
    const auto [it, fresh] = seen.emplace(target, k);
    if (!fresh) {
      const auto& [other_option, other_path] = outputs[it->second];
      throw InputError(option + " '" + path + "' and " + other_option + " '" + other_path + "' are the same file (" +
                       target + "); give each output its own file");
    }
  }
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  target_ = resolved_output_path(path_);
  check_target(target_, "output '" + path_ + "'");
  owner_ = ::getpid();
  tmp_ = target_ + ".tmp." + std::to_string(owner_);
  slot_ = register_temporary(tmp_, path_);  // before the file exists, see g_slots
  out_.open(tmp_, std::ios::out | std::ios::trunc);
  if (!out_) {
    const int e = errno;
    unregister_temporary(slot_);
    throw InputError("cannot write '" + path_ + "'" + errno_text(e));
  }
  out_.precision(17);
}

AtomicFile::~AtomicFile() {
  if (!committed_ && owner_ == ::getpid()) {  // a forked child's copy leaves its parent's file
    out_.close();
    ::unlink(tmp_.c_str());
    unregister_temporary(slot_);  // after the file is gone, see g_slots
  }
}

void AtomicFile::finish() {
  if (!out_.is_open()) return;
  errno = 0;
  out_.flush();
  if (!out_) throw InputError("error while writing '" + path_ + "'" + errno_text(errno));
  out_.close();
  if (out_.fail()) throw InputError("error while writing '" + path_ + "'" + errno_text(errno));
}

void AtomicFile::rename_into_place() {
  if (std::rename(tmp_.c_str(), target_.c_str()) != 0)
    throw InputError("cannot move output into place at '" + path_ + "'" + errno_text(errno));
  committed_ = true;
  unregister_temporary(slot_);
}

void AtomicFile::commit() {
  finish();
  commit_together({this});
}

void commit_together(std::initializer_list<AtomicFile*> files) {
  for (AtomicFile* f : files)
    if (f) f->finish();
  // With the cleanup signals held back, a signal arriving now is handled after every rename:
  // the run's outputs are then all in place, never some of them.
  const sigset_t block = cleanup_signal_set();
  sigset_t old;
  pthread_sigmask(SIG_BLOCK, &block, &old);
  try {
    for (AtomicFile* f : files)
      if (f && !f->committed_) f->rename_into_place();
  } catch (...) {
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    throw;
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
}

void install_cleanup_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = remove_temporaries_and_die;
  sa.sa_mask = cleanup_signal_set();  // one cleanup at a time
  sa.sa_flags = 0;
  for_each_cleanup_signal([&](int s) {
    // Only the default action is replaced: a signal that is ignored, or handled by the host
    // program (Python's KeyboardInterrupt), does not end the process here.
    struct sigaction old {};
    if (sigaction(s, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) return;
    sigaction(s, &sa, nullptr);
  });
}

}  // namespace hardsphere
