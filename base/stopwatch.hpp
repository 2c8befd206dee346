#pragma once
// Adds the wall time of a scope to a running total (the parts of a time step that runs report).
#include <mpi.h>

namespace ibvalve::base {

class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), start_(MPI_Wtime()) {}
  ~Stopwatch() { total_ += MPI_Wtime() - start_; }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  double start_;
};

} // namespace ibvalve::base
