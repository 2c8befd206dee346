#pragma once
// Failures that reach every rank. Work that one rank does for all (rank 0 creating the run folder,
// cutting timeseries.csv, listing checkpoints) must not leave the other ranks waiting in the next
// collective call when it throws: its error is handed to every rank, which all throw it, so every rank
// ends with the same message and exit code (InputError 2, RunError 3, anything else 1).
#include <exception>
#include <filesystem>
#include <functional>

#include <mpi.h>

namespace ibvalve::io {

/// Collective over `comm`: every rank passes what it caught (nullptr for nothing). When any rank
/// failed, every rank throws the error of the lowest failing rank, of the same kind (InputError,
/// RunError, else std::runtime_error) and with the same message; otherwise it returns.
void rethrow_on_every_rank(MPI_Comm comm, std::exception_ptr error);

/// Runs `work` on rank 0 of `comm` only, then rethrow_on_every_rank. Collective.
void on_root(MPI_Comm comm, const std::function<void()>& work);

/// Rank 0 creates `directory` (and its parents) for a running model's output (fields/, fftw_wisdom/):
/// RunError naming it on every rank when it cannot. Collective.
void create_directories_on_root(MPI_Comm comm, const std::filesystem::path& directory);

} // namespace ibvalve::io
