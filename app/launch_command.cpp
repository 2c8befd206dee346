#include "app/launch_command.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <string_view>

#include <unistd.h>

namespace ibvalve::app {

namespace {

/// The NUL-separated argument list of /proc/<pid>/cmdline (empty when it cannot be read).
std::vector<std::string> command_line_of(const std::string& pid)
{
  std::ifstream in("/proc/" + pid + "/cmdline", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> words;
  std::string word;
  for (char c : text) {
    if (c != '\0') {
      word += c;
      continue;
    }
    words.push_back(word);
    word.clear();
  }
  if (!word.empty()) words.push_back(word);
  return words;
}

} // namespace

LaunchCommand launch_command_from(const std::vector<std::string>& parent, const std::vector<std::string>& own,
                                  int launcher_ranks)
{
  LaunchCommand command;
  command.program = own.empty() ? std::string("ibvalve") : own.front();
  if (const auto dashes = std::find(own.begin(), own.end(), "--"); dashes != own.end())
    command.petsc.assign(std::next(dashes), own.end());
  if (launcher_ranks <= 0) return command;
  // mpiexec's words before this program, when the parent's command line names it.
  const auto program = std::find(parent.begin(), parent.end(), command.program);
  if (!parent.empty() && program != parent.end() && program != parent.begin())
    command.launcher.assign(parent.begin(), program);
  else
    command.launcher = {"mpiexec", "-n", std::to_string(launcher_ranks)};
  return command;
}

LaunchCommand launch_command()
{
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const int ranks = size != nullptr ? std::atoi(size) : 0;
  return launch_command_from(ranks > 0 ? command_line_of(std::to_string(getppid()))
                                       : std::vector<std::string>{},
                             command_line_of("self"), ranks);
}

std::string shell_quoted(const std::string& word)
{
  const bool safe = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) ||
           std::string_view("_-./=:,+@%^").find(c) != std::string_view::npos;
  });
  if (safe) return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string restart_command(const LaunchCommand& command, const std::filesystem::path& run_directory)
{
  std::vector<std::string> words = command.launcher;
  for (const std::string& w :
       {command.program, std::string("run"), std::string("--restart"), run_directory.string()})
    words.push_back(w);
  if (!command.petsc.empty()) {
    words.emplace_back("--");
    words.insert(words.end(), command.petsc.begin(), command.petsc.end());
  }
  std::string line;
  for (const std::string& w : words) line += (line.empty() ? "" : " ") + shell_quoted(w);
  return line;
}

} // namespace ibvalve::app
