#include "app/fftw_plans.hpp"

#include <filesystem>

#include <mpi.h>

#include "fluid/fft_stokes.hpp"
#include "io/files.hpp"
#include "io/logger.hpp"

namespace ibvalve::app {

namespace {

std::filesystem::path wisdom_file(const RunContext& context)
{
  return context.run_directory / "fftw_wisdom.txt";
}

} // namespace

void load_fftw_plans(const RunContext& context)
{
  int rank = 0;
  MPI_Comm_rank(context.comm, &rank);
  int present = rank == 0 && std::filesystem::is_regular_file(wisdom_file(context)) ? 1 : 0;
  MPI_Bcast(&present, 1, MPI_INT, 0, context.comm);
  if (!present) return; // a run of an older build: the plans are timed anew (round-off differences)
  const std::string wisdom = rank == 0 ? io::read_text_file(wisdom_file(context)) : std::string();
  if (!fluid::import_fftw_wisdom(context.comm, wisdom))
    io::Logger::global().warn(wisdom_file(context).string() +
                              ": FFTW did not accept these plans (another FFTW build?); the transforms are "
                              "planned anew and the restart agrees with the run to round-off only");
}

void save_fftw_plans(const RunContext& context)
{
  const std::string wisdom = fluid::export_fftw_wisdom(context.comm);
  int rank = 0;
  MPI_Comm_rank(context.comm, &rank);
  if (rank == 0) io::write_file_atomically(wisdom_file(context), wisdom);
}

} // namespace ibvalve::app
