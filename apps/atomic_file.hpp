// Output files written atomically: the bytes go to a temporary file beside the target
// (NAME.tmp.PID), which is renamed onto the final name only when complete. An interrupted run
// leaves the previous file (or none) under the final name, never a half-written one; a run killed
// outright leaves its temporary file, which the next write of that target removes once its
// process is gone.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace tumble::app {

class AtomicFile {
 public:
  // Opens a temporary file in the target's directory; throws std::runtime_error naming the
  // path when it cannot.
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();  // removes the temporary file unless commit() succeeded
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // Throws std::runtime_error naming the target and the system's reason ("No space left on
  // device") once a write to stream() has failed. Writers call it after each record, while errno
  // still holds the failed write's reason, so that a full disk stops a run at once and says why.
  void check() const;
  // Flushes, closes and renames onto the target. Throws std::runtime_error on any failure.
  void commit();
  const std::filesystem::path& target() const { return target_; }

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes `contents` to `target` atomically.
void write_file_atomically(const std::filesystem::path& target, const std::string& contents);

}  // namespace tumble::app
