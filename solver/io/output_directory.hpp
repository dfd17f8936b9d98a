#pragma once
// The output directory of one run. Created (or checked) before any work, with errors
// that name it; locked, so that a second run into the same directory at the same
// time stops at once instead of overwriting the first; and cleared of a previous run's
// outputs, so that nothing there is mistaken for this run's (a diverging run never
// calls an old restart.h5 "the last good one"). A run continuing from a restart keeps
// the directory's history.csv (it continues it), and its restart.h5 when that is the
// file it continues from. Temporary files left by a killed write are removed.
#include <string>
#include <vector>

namespace narwhal {

class OutputDirectory {
 public:
  OutputDirectory(const std::string& path, bool keep_history, bool keep_restart);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  // Files of a previous run that were removed (empty when none).
  const std::vector<std::string>& cleared() const { return cleared_; }

  // The names of the files a run writes (everything cleared between runs).
  static bool is_run_output(const std::string& filename);

 private:
  int lock_fd_ = -1;
  std::vector<std::string> cleared_;
};

// True when `restart` is the restart.h5 of directory `out_dir` (a run continuing in place).
bool restart_is_in(const std::string& restart, const std::string& out_dir);

}  // namespace narwhal
