#pragma once
// Files a run writes: never half-written. A file is written beside its final name and renamed into
// place, so a reader (or a crash) sees the old file or the new one, never a torn one.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace ibvalve::io {

/// Writes `content` to `path` atomically (temporary file + rename). A failure (a full disk) is a
/// RunError "PATH: cannot write: <OS reason>", and no temporary file is left.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

// Size limits of the files read whole (a file beyond its limit is bad input, refused before reading):
// far above what ibvalve writes or a user's table holds, so that a huge or sparse file given by
// mistake is named in a second and not read for minutes into memory.

/// JSON, fibers files, templates, case files.
inline constexpr std::uintmax_t max_text_bytes = std::uintmax_t{256} << 20;
/// CSV series (timeseries.csv).
inline constexpr std::uintmax_t max_table_bytes = std::uintmax_t{2} << 30;
/// A waveform or a biaxial sample: a table of some thousand rows.
inline constexpr std::uintmax_t max_input_table_bytes = std::uintmax_t{64} << 20;
/// A .msh file: millions of elements.
inline constexpr std::uintmax_t max_mesh_bytes = std::uintmax_t{512} << 20;

/// InputError naming `path` unless it is a regular file (a FIFO or a device could block or never end,
/// a folder is no file) of at most `max_bytes` bytes. Symbolic links are followed.
void check_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

/// Creates `folder` and its parents for a command's output: InputError "FOLDER: cannot create the
/// output folder (OS reason)" when it cannot be made (a path below a regular file, in /proc, without
/// permission), so that a wrong -o is bad input and not an internal error.
void create_output_folder(const std::filesystem::path& folder);

/// Reads a whole text file (check_input_file first); InputError when it cannot be read.
std::string read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes = max_text_bytes);

/// Appends rows to a CSV time series, flushing each row so a run that stops keeps every row so far.
/// The header is written when the file is created; reopening an existing file (restart) appends.
/// With `units` (one per column; "1" for a pure number) a comment line `# units: s,mL/s,...` follows
/// the header: the column names stay plain identifiers for every reader, and readers that skip '#'
/// lines (read_csv, pandas comment='#', numpy genfromtxt/loadtxt) see a plain table (docs/runs.md).
/// A write that fails (a full disk) is a RunError "PATH: cannot write: <OS reason>", and the file is
/// cut back to its last whole row.
class CsvWriter {
 public:
  CsvWriter() = default;
  CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns, bool append = false,
            const std::vector<std::string>& units = {});
  void write_row(const std::vector<double>& values);
  const std::vector<std::string>& columns() const { return columns_; }
  bool is_open() const { return out_.is_open(); }

 private:
  void put(const std::string& text);

  std::filesystem::path path_;
  std::ofstream out_;
  std::vector<std::string> columns_;
  std::uintmax_t complete_size_ = 0; // bytes of whole lines written
};

/// A CSV table of numbers with a header row (comment lines start with '#').
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  /// Index of a column; InputError naming the file when it is missing.
  std::size_t column(std::string_view name) const;
  std::vector<double> values(std::string_view name) const;
  std::filesystem::path source;
};

/// `text` with &, <, > and " as XML entities: text and attribute values of XML and HTML files, which
/// may carry names from a user's files (mesh groups, case names).
std::string xml_escaped(std::string_view text);

/// Why `name` cannot be the name of one folder inside another ("" when it can): empty, "." or "..",
/// or holding '/', '\\' or a control character. Run and study case names become folders, and a name
/// is not a path: "../x" would put a run outside the folder meant for it.
std::string folder_name_problem(std::string_view name);

/// `s` without leading and trailing blanks (spaces, tabs, carriage returns).
std::string trim(std::string_view s);
/// The comma-separated fields of one CSV line, each trimmed (a trailing comma gives an empty field).
std::vector<std::string> split_csv_line(const std::string& line);

/// Reads a CSV file of numbers (check_input_file first). `header` false means the first row is data
/// (columns named c0, c1, ...). A malformed line, or a column named twice in the header (a reader by
/// name would take one of them silently), throws InputError "file:line: ...".
CsvTable read_csv(const std::filesystem::path& path, bool header = true,
                  std::uintmax_t max_bytes = max_table_bytes);

} // namespace ibvalve::io
