#include "app/fftw_plans.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <string>

#include <mpi.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fluid/fft_stokes.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"

namespace ibvalve::app {

namespace {

/// This rank's file: every rank times its own serial transforms and may choose differently, so each
/// keeps its own plans (for a restart on the same number of ranks).
std::filesystem::path wisdom_file(const RunContext& context)
{
  int rank = 0, size = 1;
  MPI_Comm_rank(context.comm, &rank);
  MPI_Comm_size(context.comm, &size);
  return context.run_directory / "fftw_wisdom" / (fmt::format("rank{}of{}.txt", rank, size));
}

} // namespace

void load_fftw_plans(const RunContext& context)
{
  const std::filesystem::path file = wisdom_file(context);
  int present = std::filesystem::is_regular_file(file) ? 1 : 0, everywhere = 0;
  MPI_Allreduce(&present, &everywhere, 1, MPI_INT, MPI_MIN, context.comm);
  // None for another rank count or a run of an older build: the plans are timed anew, and the
  // restart agrees with the run to round-off.
  if (!everywhere) return;
  int accepted = fluid::import_fftw_wisdom(io::read_text_file(file)) ? 1 : 0, all = 0;
  MPI_Allreduce(&accepted, &all, 1, MPI_INT, MPI_MIN, context.comm);
  if (!all)
    base::Logger::global().warn(
        file.parent_path().string() +
        ": FFTW did not accept the run's plans (another FFTW build?); the transforms are "
        "planned anew and the restart agrees with the run to round-off only");
}

void save_fftw_plans(const RunContext& context)
{
  io::create_directories_on_root(context.comm, context.run_directory / "fftw_wisdom");
  // Each rank writes its own plans; one that cannot stops every rank (before the checkpoint, which is
  // collective).
  std::exception_ptr error;
  try {
    io::write_file_atomically(wisdom_file(context), fluid::export_fftw_wisdom());
  } catch (const std::exception& e) {
    error = std::make_exception_ptr(RunError(wisdom_file(context).string() + ": " + e.what()));
  }
  io::rethrow_on_every_rank(context.comm, error);
}

} // namespace ibvalve::app
