#pragma once
// A page's plots: drawn by the embedded script (hemodynamics/plot_report.py) in a Python of its own,
// then listed for the page's templates. `ibvalve report` and `ibvalve compare` both draw this way.
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <kainjow/mustache.hpp>

namespace ibvalve::hemodynamics {

/// The Python this build found (CMake's Python3_EXECUTABLE, with numpy and matplotlib): the default
/// interpreter of every plot.
const char* default_python();

/// The embedded plotting script (hemodynamics/plot_report.py): a report's plots, and with --compare a
/// comparison's curves.
const char* plot_report_script();

/// One image a page may show: its file name in the output folder and its caption.
struct PlotCaption {
  const char* file;
  const char* caption;
};

struct DrawnPlots {
  std::vector<std::filesystem::path> files; // the expected images that exist afterwards, in order
  std::string problem;                      // "" when the script succeeded, else one line naming the log
};

/// Removes `expected`'s images from `folder` (none is left from an earlier drawing), then, with
/// `draw`, writes plot_report.py and plot_log.txt there and runs `python -I plot_report.py
/// script_arguments...` from "/": isolated (-I: neither the script's folder, the output folder, nor
/// the working directory, user site-packages or PYTHON* variables reach sys.path), with no shell
/// between, so a json.py or matplotlib.py planted beside the output is never imported.
DrawnPlots draw_plots(bool draw, const std::string& python, const std::vector<std::string>& script_arguments,
                      const std::filesystem::path& folder, std::span<const PlotCaption> expected);

/// Removes `expected`'s images from `folder`, so that none is left from an earlier drawing.
void remove_plots(const std::filesystem::path& folder, std::span<const PlotCaption> expected);

/// A report's pages drawn by one Python (matplotlib imported and the series read once): `expected`'s
/// images removed from every folder, then, with `draw`, plot_report.py written into each (to draw that
/// page again by hand) and run as draw_plots runs it, on `series` and each folder's metrics.json, its log
/// in the first folder's plot_log.txt. One DrawnPlots a folder, in order; the first carries the problem.
std::vector<DrawnPlots> draw_page_plots(bool draw, const std::string& python,
                                        const std::filesystem::path& series,
                                        std::span<const std::filesystem::path> folders,
                                        std::span<const PlotCaption> expected);

/// The templates' `plots` list: file, caption and png_base64 of each drawn image.
kainjow::mustache::data plot_template_rows(std::span<const std::filesystem::path> plots,
                                           std::span<const PlotCaption> captions);

/// Runs `args` (args[0] looked up in PATH unless it holds a '/') with no shell between, in `directory`,
/// stdin from /dev/null, stdout and stderr into `log`, and waits for it: "" when it exited with 0, else
/// what went wrong (one line).
std::string run_program(const std::vector<std::string>& args, const std::filesystem::path& directory,
                        const std::filesystem::path& log);

/// Base64 of binary data (RFC 4648), for images embedded in HTML.
std::string base64(std::string_view data);

} // namespace ibvalve::hemodynamics
