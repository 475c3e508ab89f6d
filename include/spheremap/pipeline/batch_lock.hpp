// One batch at a time in an output root (stage: pipeline).
#pragma once

#include <filesystem>

namespace spheremap {

/// Holds an exclusive lock (flock on `root/.batch.lock`, created with `root` if missing) so that two
/// batches never write into the same root; released on destruction or when the process ends, however.
/// Throws InputError if the root cannot be created or another process holds the lock.
class BatchLock {
 public:
  explicit BatchLock(const std::filesystem::path& root);
  ~BatchLock();
  BatchLock(const BatchLock&) = delete;
  BatchLock& operator=(const BatchLock&) = delete;
  /// In a process forked while the lock is held: closes this process's copy of the lock's descriptor, so
  /// that the lock ends with the process that took it, not with the last of its children (a flock
  /// belongs to the open file, which a fork shares). Does not throw.
  void forget_in_child() const noexcept;

 private:
  int descriptor_ = -1;
};

}  // namespace spheremap
