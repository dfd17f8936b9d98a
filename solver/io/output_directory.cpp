#include "io/output_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "core/error.hpp"

namespace narwhal {
namespace fs = std::filesystem;

bool OutputDirectory::is_run_output(const std::string& n) {
  if (n == "history.csv" || n == "run.json" || n == "restart.h5" || n == "solution.cgns")
    return true;
  return n.rfind("surface_", 0) == 0 && n.size() > 12 && n.compare(n.size() - 4, 4, ".csv") == 0;
}

bool restart_is_in(const std::string& restart, const std::string& out_dir) {
  std::error_code ec;
  const fs::path own = fs::path(out_dir) / "restart.h5";
  return fs::exists(own, ec) && fs::equivalent(restart, own, ec) && !ec;
}

OutputDirectory::OutputDirectory(const std::string& path, bool keep_history, bool keep_restart) {
  if (path.empty()) fail("--out: the output directory name is empty");
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec))
    fail("--out '{}': exists and is not a directory", path);
  fs::create_directories(path, ec);
  if (ec) fail("--out '{}': cannot create the output directory: {}", path, ec.message());
  const std::string lock = (fs::path(path) / ".narwhal.lock").string();
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) fail("--out '{}': the directory is not writable: {}", path, std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {};
    const ssize_t n = ::pread(lock_fd_, pid, sizeof pid - 1, 0);
    ::close(lock_fd_);
    lock_fd_ = -1;
    fail("--out '{}': another narwhal run (pid {}) is writing into this directory; choose another --out",
         path, n > 0 ? std::string(pid, static_cast<std::size_t>(n)) : std::string("?"));
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) < 0)
    fail("--out '{}': cannot write its lock file: {}", path, std::strerror(errno));
  for (const auto& entry : fs::directory_iterator(path, ec)) {
    const std::string name = entry.path().filename().string();
    // Temporary files of a write that was killed half way are never anyone's output.
    const bool temporary = name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0 &&
                           is_run_output(name.substr(0, name.size() - 4));
    const bool kept = (keep_history && name == "history.csv") || (keep_restart && name == "restart.h5");
    if (!temporary && (kept || !is_run_output(name))) continue;
    fs::remove(entry.path(), ec);
    if (ec) fail("--out '{}': cannot remove the previous run's '{}': {}", path, name, ec.message());
    if (!temporary) cleared_.push_back(name);
  }
  if (ec) fail("--out '{}': cannot list the directory: {}", path, ec.message());
}

OutputDirectory::~OutputDirectory() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock
}

}  // namespace narwhal
