// BatchLock: an flock on root/.batch.lock.
#include "spheremap/pipeline/batch_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {

namespace fs = std::filesystem;

BatchLock::BatchLock(const fs::path& root) {
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder: {}", root.string(), ec.message()));
  const fs::path lock = root / ".batch.lock";
  descriptor_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor_ < 0)
    throw InputError(fmt::format("{}: cannot create the lock file ({}); check that the output folder is writable",
                                 lock.string(), std::strerror(errno)));
  if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(descriptor_);
    descriptor_ = -1;
    if (error == EWOULDBLOCK)
      throw InputError(
          fmt::format("{}: another spheremap batch is writing into this folder; wait for it to end, "
                      "or choose another -o folder",
                      root.string()));
    throw InputError(fmt::format("{}: cannot lock the output folder ({})", root.string(), std::strerror(error)));
  }
}

BatchLock::~BatchLock() {
  if (descriptor_ >= 0) ::close(descriptor_);  // closing releases the flock
}

void BatchLock::forget_in_child() const noexcept {
  if (descriptor_ >= 0) ::close(descriptor_);  // this process's descriptor only: the parent keeps the lock
}

}  // namespace spheremap
