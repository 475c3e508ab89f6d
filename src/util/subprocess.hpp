// Private to the library: running an external program (pdb2pqr, APBS) in a temporary folder.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace spheremap::detail {

/// A new empty folder under the system's temporary folder, removed with everything in it on destruction.
/// Throws std::runtime_error when it cannot be made.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The executable `name` found on PATH, if any.
std::optional<std::filesystem::path> find_executable(const std::string& name);

struct ProgramRun {
  int exit_code = -1;    // the program's exit status; -1 if it was killed by a signal
  double seconds = 0;    // wall-clock time
  std::string log_tail;  // the last lines of what it wrote to stdout and stderr
};

/// Runs `arguments` (arguments[0] an executable path) in `folder`, stdin from /dev/null, stdout and stderr
/// to `log` (a file), and waits for it; `waiting`, if set, is called about every `interval` with the time
/// spent so far. Throws std::runtime_error when the program cannot be started.
ProgramRun run_program(const std::vector<std::string>& arguments, const std::filesystem::path& folder,
                       const std::filesystem::path& log, const std::function<void(double seconds)>& waiting = nullptr,
                       std::chrono::milliseconds interval = std::chrono::seconds(5));

/// The last `lines` lines of a text file ("" when it cannot be read).
std::string file_tail(const std::filesystem::path& path, int lines);

}  // namespace spheremap::detail
