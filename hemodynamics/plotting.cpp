#include "hemodynamics/plotting.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include "io/files.hpp"

namespace ibvalve::hemodynamics {

namespace fs = std::filesystem;

void remove_plots(const fs::path& folder, std::span<const PlotCaption> expected)
{
  for (const PlotCaption& plot : expected) fs::remove(folder / plot.file);
}

DrawnPlots draw_plots(bool draw, const std::string& python, const std::vector<std::string>& script_arguments,
                      const fs::path& folder, std::span<const PlotCaption> expected)
{
  remove_plots(folder, expected);
  DrawnPlots out;
  if (!draw) return out;
  const fs::path script = folder / "plot_report.py";
  const fs::path log = folder / "plot_log.txt";
  io::write_file_atomically(script, plot_report_script());
  std::vector<std::string> args{python, "-I", fs::absolute(script).string()};
  args.insert(args.end(), script_arguments.begin(), script_arguments.end());
  if (const std::string problem = run_program(args, "/", log); !problem.empty())
    out.problem = "plotting with " + python + " failed (" + log.string() + "): " + problem;
  for (const PlotCaption& plot : expected)
    if (fs::exists(folder / plot.file)) out.files.push_back(folder / plot.file);
  return out;
}

std::vector<DrawnPlots> draw_page_plots(bool draw, const std::string& python, const fs::path& series,
                                        std::span<const fs::path> folders,
                                        std::span<const PlotCaption> expected)
{
  std::vector<DrawnPlots> out(folders.size());
  for (const fs::path& folder : folders) remove_plots(folder, expected);
  if (!draw || folders.empty()) return out;
  std::vector<std::string> args{python, "-I", fs::absolute(folders.front() / "plot_report.py").string(),
                                fs::absolute(series).string()};
  for (const fs::path& folder : folders) {
    io::write_file_atomically(folder / "plot_report.py", plot_report_script());
    args.push_back(fs::absolute(folder / "metrics.json").string());
    args.push_back(fs::absolute(folder).string());
  }
  const fs::path log = folders.front() / "plot_log.txt";
  if (const std::string problem = run_program(args, "/", log); !problem.empty())
    out.front().problem = "plotting with " + python + " failed (" + log.string() + "): " + problem;
  for (std::size_t i = 0; i < folders.size(); ++i)
    for (const PlotCaption& plot : expected)
      if (fs::exists(folders[i] / plot.file)) out[i].files.push_back(folders[i] / plot.file);
  return out;
}

kainjow::mustache::data plot_template_rows(std::span<const fs::path> plots,
                                           std::span<const PlotCaption> captions)
{
  using kainjow::mustache::data;
  data rows{data::type::list};
  for (const fs::path& p : plots) {
    std::string caption;
    for (const PlotCaption& c : captions)
      if (p.filename() == c.file) caption = c.caption;
    data row;
    row.set("file", p.filename().string());
    row.set("caption", caption);
    row.set("png_base64", base64(io::read_text_file(p)));
    rows.push_back(row);
  }
  return rows;
}

std::string run_program(const std::vector<std::string>& args, const fs::path& directory, const fs::path& log)
{
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int error = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) return "cannot start " + args[0] + " (" + std::strerror(error) + ")";
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return "lost " + args[0] + " (" + std::strerror(errno) + ")";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFSIGNALED(status)) return fmt::format("{} was killed by signal {}", args[0], WTERMSIG(status));
  std::string tail = fs::exists(log) ? io::read_text_file(log) : std::string();
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r')) tail.pop_back();
  const auto cut = tail.rfind('\n');
  return fmt::format(
      "exit {}{}", WEXITSTATUS(status),
      (tail.empty() ? std::string() : ": " + (cut == std::string::npos ? tail : tail.substr(cut + 1))));
}

std::string base64(std::string_view data)
{
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16 |
                       static_cast<unsigned char>(data[i + 1]) << 8 | static_cast<unsigned char>(data[i + 2]);
    out += alphabet[v >> 18 & 63];
    out += alphabet[v >> 12 & 63];
    out += alphabet[v >> 6 & 63];
    out += alphabet[v & 63];
  }
  if (i + 1 == data.size()) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16;
    out += alphabet[v >> 18 & 63];
    out += alphabet[v >> 12 & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16 | static_cast<unsigned char>(data[i + 1])
                                                                       << 8;
    out += alphabet[v >> 18 & 63];
    out += alphabet[v >> 12 & 63];
    out += alphabet[v >> 6 & 63];
    out += '=';
  }
  return out;
}

} // namespace ibvalve::hemodynamics
