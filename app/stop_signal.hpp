#pragma once
// SIGINT (Ctrl-C) and SIGTERM (a batch system's notice) stop a run cleanly (docs/runs.md): the run
// finishes its step, writes a checkpoint, keeps its output and exits with 128 + the signal's number
// (130, 143), to be continued with `ibvalve run --restart`. A signal may reach one rank only (or the
// ranks at different moments): the ranks agree on it each step (agreed_stop_signal), so they stop at
// the same step and write the checkpoint together. A second signal of the same kind ends the process
// at once, as without the handler. Under mpiexec a Ctrl-C reaches the ranks as mpiexec's SIGTERM.
#include <string>

#include <mpi.h>

namespace ibvalve::app {

/// Notes SIGINT and SIGTERM instead of dying of them (ibvalve run, before the model runs).
void catch_stop_signals();

/// The signal this process has noted (SIGINT or SIGTERM), 0 for none.
int noted_stop_signal();

/// Collective over `comm`: the signal any rank has noted (SIGTERM when both were), 0 for none.
int agreed_stop_signal(MPI_Comm comm);

/// "SIGINT", "SIGTERM".
std::string signal_name(int signal);

/// The agreed `signal` as the stopped line names it: its name, and where this process noted it from
/// Open MPI's mpiexec (its parent sent it under OMPI_COMM_WORLD_SIZE), that it is mpiexec's forwarding
/// of a Ctrl-C or a SIGTERM, which a rank cannot tell apart (docs/runs.md).
std::string stop_signal_description(int signal);

/// The exit code of a run stopped by `signal`: 128 + its number (130 for SIGINT, 143 for SIGTERM).
inline int exit_code_of_signal(int signal)
{
  return 128 + signal;
}

} // namespace ibvalve::app
