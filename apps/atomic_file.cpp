#include "apps/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace tumble::app {
namespace {

// A process killed outright (SIGKILL, a power cut) leaves its NAME.tmp.PID behind: the next file
// written to NAME removes those whose process no longer exists.
void remove_stale_temporaries(const std::filesystem::path& target) {
  const std::string prefix = target.filename().string() + ".tmp.";
  std::error_code ec;
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(prefix))
      continue;
    long pid = 0;
    const char* first = name.data() + prefix.size();
    const char* last = name.data() + name.size();
    const auto [end, error] = std::from_chars(first, last, pid);
    if (error != std::errc() || end != last || pid <= 0 || pid == ::getpid())
      continue;
    if (::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) {
      std::error_code ignored;
      std::filesystem::remove(entry.path(), ignored);
    }
  }
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  remove_stale_temporaries(target_);
  // The temporary lives in the same directory so the final rename never crosses file systems
  // (rename(2) is atomic only within one).
  temporary_ = target_;
  temporary_ += ".tmp." + std::to_string(::getpid());
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error(target_.string() + ": cannot open for writing (" +
                             std::strerror(errno) + ")");
  }
}

AtomicFile::~AtomicFile() {
  if (committed_)
    return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

void AtomicFile::check() const {
  if (out_)
    return;
  std::string message = target_.string();
  message += ": write failed";
  if (errno != 0) {
    message += " (";
    message += std::strerror(errno);
    message += ")";
  }
  throw std::runtime_error(message);
}

void AtomicFile::commit() {
  if (out_) {
    errno = 0;
    out_.flush();
  }
  check();
  out_.close();
  std::error_code ec;
  std::filesystem::rename(temporary_, target_, ec);
  if (ec)
    throw std::runtime_error(target_.string() + ": cannot rename into place (" + ec.message() +
                             ")");
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& target, const std::string& contents) {
  AtomicFile file(target);
  file.stream() << contents;
  file.commit();
}

}  // namespace tumble::app
