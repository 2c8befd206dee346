#include "app/stop_signal.hpp"

#include <csignal>
#include <cstdlib>
#include <fmt/format.h>

#include <signal.h>
#include <unistd.h>

namespace ibvalve::app {

namespace {

volatile std::sig_atomic_t noted = 0;
volatile std::sig_atomic_t noted_from_parent = 0; // the noted signal's sender was this process's parent

extern "C" void note_signal(int signal, siginfo_t* info, void*)
{
  // SIGTERM wins over SIGINT when both arrive (the batch system's notice is the one to answer to).
  if (noted == SIGTERM) return;
  noted = signal;
  noted_from_parent = info != nullptr && info->si_code == SI_USER && info->si_pid == getppid() ? 1 : 0;
}

} // namespace

void catch_stop_signals()
{
  struct sigaction action {};
  action.sa_sigaction = note_signal;
  sigemptyset(&action.sa_mask);
  // SA_RESETHAND: a second signal of the kind finds the default action and ends the process.
  // SA_SIGINFO: the sender's pid, which tells mpiexec's forwarding apart.
  action.sa_flags = SA_RESTART | SA_RESETHAND | SA_SIGINFO;
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

std::string stop_signal_description(int signal)
{
  const std::string name = signal_name(signal);
  if (signal != noted || !noted_from_parent || std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr) return name;
  // Open MPI's mpiexec passes SIGINT (a Ctrl-C) and SIGTERM on to the ranks as SIGTERM, and nothing in
  // what a rank receives tells which one it was given.
  return name + " from mpiexec (a Ctrl-C or a SIGTERM to mpiexec: it passes both on as SIGTERM)";
}

std::string signal_name(int signal)
{
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return fmt::format("signal {}", signal);
}

} // namespace ibvalve::app
