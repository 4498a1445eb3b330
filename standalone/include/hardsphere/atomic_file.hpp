#pragma once
//! Output files that appear complete or not at all: each is written under a temporary name
//! (the target's name + ".tmp." + pid, in the target's directory) and renamed into place only
//! when the whole run succeeded. Every open temporary is listed in a fixed table that a signal
//! handler can read without allocating, so a terminating signal removes them too.
#include <sys/types.h>

#include <fstream>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace hardsphere {

//! A file written under a temporary name and moved into place by commit(). Destroying it
//! uncommitted removes the temporary. Two AtomicFiles may not write the same file (any
//! spelling): the second throws InputError.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::ofstream& stream() { return out_; }
  void commit();  //!< finish() then rename into place
  //! Flush and close, throwing InputError on any write error; the temporary stays until commit.
  void finish();
  const std::string& path() const { return path_; }  //!< as the caller spelled it
  const std::string& temporary() const { return tmp_; }

 private:
  friend void commit_together(std::initializer_list<AtomicFile*> files);
  void rename_into_place();

  std::string path_, target_, tmp_;
  std::ofstream out_;
  int slot_ = -1;  // entry in the signal handler's table
  pid_t owner_{};  // the process that made the temporary (a forked child leaves it alone)
  bool committed_ = false;
};

//! Finishes every file given (null entries are skipped), then renames them all with the
//! cleanup signals blocked, so a signal either removes every temporary or finds them all in place.
void commit_together(std::initializer_list<AtomicFile*> files);

//! Installs handlers for every catchable signal whose default action ends the process (SIGHUP,
//! SIGINT, SIGTERM, SIGUSR1/2, SIGALRM, SIGPIPE, SIGABRT, faults, real-time signals, ...) that
//! remove every open temporary file of this process, then let the process die by the same
//! signal (default action re-raised). Only signals at their default action are taken: one that
//! is ignored at the time of the call (e.g. SIGHUP under nohup) stays ignored, and one that has
//! a handler keeps it (the host's handler decides whether the process ends; Python's
//! KeyboardInterrupt stays). Calling it again takes signals set back to the default since.
//! The CLI calls this once; the Python module before each file it writes.
void install_cleanup_signal_handlers();

//! The absolute path a file name refers to, with symlinks resolved as far as the path exists
//! ("./x", "d/../x" and a link to x are all x). Throws InputError if it cannot be determined.
std::string resolved_output_path(const std::string& path);

//! Refuses (InputError, before anything is created) output paths that are directories, lie in a
//! directory that does not exist, or name the same file as another output. Entries are
//! (option name, path); "-" (standard output) is skipped.
void check_output_paths(const std::vector<std::pair<std::string, std::string>>& outputs);

}  // namespace hardsphere
