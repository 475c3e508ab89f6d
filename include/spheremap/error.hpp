// Errors that reach the user. Each carries the exit code the CLI returns for it.
#pragma once

#include <stdexcept>
#include <string>

namespace spheremap {

/// Exit codes of the command-line tool (documented in the README).
enum class ExitCode : int {
  kOk = 0,
  kUsage = 1,         // bad command line, unreadable or malformed input file
  kRefusedMesh = 2,   // the mesh is readable but cannot be mapped (open, non-manifold, genus != 0, ...)
  kNotCertified = 3,  // a map was written but it is not certified (folded or collapsed triangles)
};

/// An error whose message is meant for the user: it names the file, the problem and the fix.
class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  [[nodiscard]] ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

/// The input file cannot be read or parsed (exit code 1).
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(ExitCode::kUsage, message) {}
};

/// The mesh was read but violates a precondition of the map (exit code 2).
class MeshRefused : public Error {
 public:
  explicit MeshRefused(const std::string& message) : Error(ExitCode::kRefusedMesh, message) {}
};

}  // namespace spheremap
