// The command a stopped run prints to continue it (app/launch_command.hpp): mpiexec and its options as
// they were given, this program as it was invoked, the PETSc options after `--`, quoted for a shell.
#include <gtest/gtest.h>

#include "app/launch_command.hpp"

using namespace ibvalve::app;

namespace {

TEST(LaunchCommand, KeepsMpiexecAndItsOptions)
{
  const LaunchCommand c = launch_command_from(
      {"mpiexec", "--oversubscribe", "-n", "2", "build/app/ibvalve", "run", "default.toml", "-o", "runs/x"},
      {"build/app/ibvalve", "run", "default.toml", "-o", "runs/x"}, 2);
  EXPECT_EQ(restart_command(c, "runs/x"),
            "mpiexec --oversubscribe -n 2 build/app/ibvalve run --restart runs/x");
}

TEST(LaunchCommand, WithoutItsCommandLineSaysMpiexecWithTheRanks)
{
  // A rank whose parent is Open MPI's daemon on another node: the launcher's words are not known.
  const LaunchCommand c =
      launch_command_from({"orted", "-mca", "ess", "env"}, {"/opt/ibvalve", "run", "a.toml"}, 4);
  EXPECT_EQ(restart_command(c, "/scratch/run"), "mpiexec -n 4 /opt/ibvalve run --restart /scratch/run");
}

TEST(LaunchCommand, WithoutALauncherIsTheProgramAlone)
{
  const LaunchCommand c = launch_command_from({"bash"}, {"ibvalve", "run", "a.toml"}, 0);
  EXPECT_EQ(restart_command(c, "runs/a"), "ibvalve run --restart runs/a");
}

TEST(LaunchCommand, KeepsThePetscOptionsAndQuotesForTheShell)
{
  const LaunchCommand c =
      launch_command_from({"mpirun", "-n", "2", "--bind-to", "none", "ibvalve", "run", "case.toml", "--",
                           "-fluid_stokes_ksp_monitor"},
                          {"ibvalve", "run", "case.toml", "--", "-fluid_stokes_ksp_monitor"}, 2);
  EXPECT_EQ(
      restart_command(c, "my runs/it's"),
      "mpirun -n 2 --bind-to none ibvalve run --restart 'my runs/it'\\''s' -- -fluid_stokes_ksp_monitor");
  EXPECT_EQ(shell_quoted("runs/a_b-1.5=x:y,z+@%"), "runs/a_b-1.5=x:y,z+@%");
  EXPECT_EQ(shell_quoted("$HOME"), "'$HOME'");
  EXPECT_EQ(shell_quoted(""), "''");
}

} // namespace
