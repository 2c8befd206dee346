#pragma once
// The two ways a run ends badly, and the exit codes the `ibvalve` command gives for them.
#include <stdexcept>
#include <string>

namespace ibvalve {

/// Exit code for bad input (a wrong key, type, range, a missing file): nothing was run or written.
inline constexpr int exit_code_input_error = 2;
/// Exit code for a run that went wrong (NaN, a diverged solver): all output so far is kept.
inline constexpr int exit_code_run_error = 3;

/// Bad input from the user. The message is one line that names the file, the line and the key.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A run that cannot go on (NaN, solver divergence, a structure that left the grid).
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

} // namespace ibvalve
