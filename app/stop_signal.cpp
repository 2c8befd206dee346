#include "app/stop_signal.hpp"

#include <csignal>
#include <fmt/format.h>

#include <signal.h>

namespace ibvalve::app {

namespace {

volatile std::sig_atomic_t noted = 0;

extern "C" void note_signal(int signal)
{
  // SIGTERM wins over SIGINT when both arrive (the batch system's notice is the one to answer to).
  if (noted != SIGTERM) noted = signal;
}

} // namespace

void catch_stop_signals()
{
  struct sigaction action {};
  action.sa_handler = note_signal;
  sigemptyset(&action.sa_mask);
  // SA_RESETHAND: a second signal of the kind finds the default action and ends the process.
  action.sa_flags = SA_RESTART | SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int noted_stop_signal()
{
  return noted;
}

int agreed_stop_signal(MPI_Comm comm)
{
  int mine = noted, agreed = 0;
  MPI_Allreduce(&mine, &agreed, 1, MPI_INT, MPI_MAX, comm);
  return agreed;
}

std::string signal_name(int signal)
{
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return fmt::format("signal {}", signal);
}

} // namespace ibvalve::app
