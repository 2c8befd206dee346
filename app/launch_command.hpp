#pragma once
// How this process was started, for the line a stopped run prints: the command that continues it,
// copied as it stands into a shell. Under Open MPI's mpiexec the rank's parent is mpiexec on the node
// it was started from, and its command line (/proc/PPID/cmdline) holds mpiexec's options before this
// program: they are kept (`mpiexec --oversubscribe -n 2 build/app/ibvalve run --restart RUN_DIR`).
// Where the parent is no such launcher (a rank on another node, whose parent is Open MPI's daemon;
// another launcher) the command is `mpiexec -n N PROGRAM ...`, N the run's ranks.
#include <filesystem>
#include <string>
#include <vector>

namespace ibvalve::app {

struct LaunchCommand {
  std::vector<std::string> launcher; ///< mpiexec and its options; empty without MPI's launcher
  std::string program;               ///< this program as it was invoked
  std::vector<std::string> petsc;    ///< the PETSc options after `--`
};

/// From the parent's and this process's argument lists (`parent` empty when unknown) and the run's
/// rank count under an MPI launcher (0 without one).
LaunchCommand launch_command_from(const std::vector<std::string>& parent, const std::vector<std::string>& own,
                                  int launcher_ranks);

/// This process's (read from /proc; Open MPI's OMPI_COMM_WORLD_SIZE tells a launcher started it).
LaunchCommand launch_command();

/// `[launcher...] program run --restart DIR [-- petsc...]`, each word quoted for a POSIX shell where it
/// needs it.
std::string restart_command(const LaunchCommand& command, const std::filesystem::path& run_directory);

/// `word` as a POSIX shell reads it back: as it is when it holds only safe characters, else in single
/// quotes.
std::string shell_quoted(const std::string& word);

} // namespace ibvalve::app
