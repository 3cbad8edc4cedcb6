// tear: the exception thrown across the library boundary, and its exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace tear {

/// What kind of failure an `Error` is; the CLI maps it to its documented exit code.
enum class ErrorKind {
  usage = 1,    ///< the command line is wrong
  input = 2,    ///< a mesh, script or other input is missing, malformed or unusable
  runtime = 3,  ///< the input was fine but the run failed (device, disk, internal)
  interrupted = 4,  ///< stopped by SIGTERM or SIGINT after a whole frame; resumable from its checkpoint
};

/// An error with a one-line message that names the file (and JSON key path) it concerns.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }
  int exit_code() const { return static_cast<int>(kind_); }

 private:
  ErrorKind kind_;
};

inline Error input_error(const std::string& file, const std::string& what) {
  return Error(ErrorKind::input, file + ": " + what);
}
inline Error runtime_error(const std::string& what) { return Error(ErrorKind::runtime, what); }

}  // namespace tear
