#include "io/collective.hpp"

#include <stdexcept>
#include <string>

#include "base/errors.hpp"

namespace ibvalve::io {

namespace {
enum Kind : int { none = 0, input = 1, run = 2, other = 3 };
}

void rethrow_on_every_rank(MPI_Comm comm, std::exception_ptr error)
{
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int kind = none;
  std::string message;
  if (error) {
    try {
      std::rethrow_exception(error);
    } catch (const InputError& e) {
      kind = input;
      message = e.what();
    } catch (const RunError& e) {
      kind = run;
      message = e.what();
    } catch (const std::exception& e) {
      kind = other;
      message = e.what();
    } catch (...) {
      kind = other;
      message = "unknown exception";
    }
  }
  const int mine = kind == none ? size : rank;
  int first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  MPI_Bcast(&kind, 1, MPI_INT, first, comm);
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, first, comm);
  if (kind == input) throw InputError(message);
  if (kind == run) throw RunError(message);
  throw std::runtime_error(message);
}

void on_root(MPI_Comm comm, const std::function<void()>& work)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::exception_ptr error;
  if (rank == 0) {
    try {
      work();
    } catch (...) {
      error = std::current_exception();
    }
  }
  rethrow_on_every_rank(comm, error);
}

void create_directories_on_root(MPI_Comm comm, const std::filesystem::path& directory)
{
  on_root(comm, [&] {
    try {
      std::filesystem::create_directories(directory);
    } catch (const std::filesystem::filesystem_error& e) {
      throw RunError(directory.string() + ": cannot create the folder (" + e.code().message() + ")");
    }
  });
}

} // namespace ibvalve::io
