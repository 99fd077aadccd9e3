#include "apps/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace tumble::app {

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
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

void AtomicFile::commit() {
  out_.flush();
  if (!out_)
    throw std::runtime_error(target_.string() + ": write failed");
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
