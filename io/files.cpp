#include "io/files.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include "base/errors.hpp"

namespace ibvalve::io {

namespace {

/// The line of a write that failed: the file and the OS reason (errno), e.g. "No space left on device".
RunError write_error(const std::filesystem::path& path, int error)
{
  return RunError(path.string() + ": cannot write: " + (error ? std::strerror(error) : "write failed"));
}

/// Writes all of `content` to the open descriptor `fd`; the errno of the write that failed, else 0.
int write_all(int fd, std::string_view content)
{
  while (!content.empty()) {
    const ssize_t written = ::write(fd, content.data(), content.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    content.remove_prefix(static_cast<std::size_t>(written));
  }
  return 0;
}

} // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view content)
{
  // POSIX calls rather than a stream: each failure has its errno, and close() is checked too (a
  // network filesystem may report a full disk only there).
  const std::filesystem::path temporary = fmt::format("{}.tmp.{}", path.string(), ::getpid());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw write_error(path, errno);
  int error = write_all(fd, content);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && std::rename(temporary.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) {
    // What was written of it goes: it would hold the space a full disk needs, under no useful name.
    ::unlink(temporary.c_str());
    throw write_error(path, error);
  }
}

void check_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes)
{
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw InputError(path.string() + ": no such file");
  if (!std::filesystem::is_regular_file(status))
    throw InputError(path.string() + ": not a regular file (" +
                     (std::filesystem::is_directory(status) ? "a folder" : "a pipe, a device or a socket") +
                     "); give a file");
  const auto size = std::filesystem::file_size(path, error);
  if (!error && size > max_bytes)
    throw InputError(fmt::format("{}: {} bytes is more than the {} MiB this file is read up to",
                                 path.string(), size, max_bytes >> 20));
}

void create_output_folder(const std::filesystem::path& folder)
{
  try {
    std::filesystem::create_directories(folder);
  } catch (const std::filesystem::filesystem_error& e) {
    throw InputError(folder.string() + ": cannot create the output folder (" + e.code().message() + ")");
  }
}

std::string read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes)
{
  check_input_file(path, max_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot be read");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

CsvWriter::CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns, bool append,
                     const std::vector<std::string>& units)
    : path_(path), columns_(std::move(columns))
{
  if (!units.empty() && units.size() != columns_.size())
    throw std::logic_error(fmt::format("CsvWriter: {} units for {} columns of {}", units.size(),
                                       columns_.size(), path.string()));
  const bool exists = append && std::filesystem::exists(path);
  errno = 0;
  out_.open(path, exists ? std::ios::app : std::ios::trunc);
  if (!out_) throw write_error(path, errno);
  out_.precision(12);
  if (!exists) {
    std::ostringstream header;
    for (std::size_t i = 0; i < columns_.size(); ++i) header << (i ? "," : "") << columns_[i];
    header << "\n";
    // A continued run appends to the file as it is: an older series without this line stays without.
    if (!units.empty()) {
      header << "# units: ";
      for (std::size_t i = 0; i < units.size(); ++i) header << (i ? "," : "") << units[i];
      header << "\n";
    }
    put(header.str());
  }
  std::error_code ignored;
  const auto size = std::filesystem::file_size(path, ignored);
  complete_size_ = ignored ? 0 : size;
}

void CsvWriter::write_row(const std::vector<double>& values)
{
  std::ostringstream row;
  row.precision(out_.precision());
  for (std::size_t i = 0; i < values.size(); ++i) row << (i ? "," : "") << values[i];
  row << "\n";
  put(row.str());
}

void CsvWriter::put(const std::string& text)
{
  errno = 0;
  out_ << text;
  out_.flush();
  if (out_) {
    complete_size_ += text.size();
    return;
  }
  const int error = errno;
  // A row cut off by a full disk is taken back, so the file ends with its last whole row (what a
  // restart from a checkpoint, or a reader, expects); the run stops here.
  out_.close();
  std::error_code ignored;
  std::filesystem::resize_file(path_, complete_size_, ignored);
  throw write_error(path_, error);
}

std::string xml_escaped(std::string_view text)
{
  std::string out;
  for (char c : text) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

std::string folder_name_problem(std::string_view name)
{
  if (name.empty()) return "must not be empty";
  if (name == "." || name == "..")
    return fmt::format("\"{}\" is not a name but a step of a path (this folder or its parent)", name);
  for (char c : name) {
    if (c == '/' || c == '\\') return fmt::format("\"{}\" holds '{}': a name, not a path", name, c);
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "holds a control character";
  }
  return "";
}

std::size_t CsvTable::column(std::string_view name) const
{
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  throw InputError(source.string() + ":1: no column '" + std::string(name) + "'");
}

std::vector<double> CsvTable::values(std::string_view name) const
{
  const std::size_t c = column(name);
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(row[c]);
  return out;
}

std::string trim(std::string_view s)
{
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return "";
  const auto last = s.find_last_not_of(" \t\r");
  return std::string(s.substr(first, last - first + 1));
}

std::vector<std::string> split_csv_line(const std::string& line)
{
  std::vector<std::string> fields;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

CsvTable read_csv(const std::filesystem::path& path, bool header, std::uintmax_t max_bytes)
{
  check_input_file(path, max_bytes);
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": no such file or not readable");
  CsvTable table;
  table.source = path;
  std::string line;
  long line_number = 0;
  bool have_header = !header;
  while (std::getline(in, line)) {
    ++line_number;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    auto fields = split_csv_line(text);
    if (!have_header) {
      for (std::size_t i = 0; i < fields.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if (fields[i] == fields[j]) {
            // The name is shown when it is one (the file may be any readable file: its text is not echoed).
            const bool identifier =
                fields[i].size() <= 40 && std::all_of(fields[i].begin(), fields[i].end(), [](char c) {
                  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
                });
            throw InputError(fmt::format(
                "{}:{}: column{} is named twice (columns {} and {}): a reader by name "
                "would take one of them",
                path.string(), line_number, identifier ? " '" + fields[i] + "'" : "", j + 1, i + 1));
          }
      table.columns = fields;
      have_header = true;
      continue;
    }
    if (table.columns.empty())
      for (std::size_t i = 0; i < fields.size(); ++i) table.columns.push_back(fmt::format("c{}", i));
    // A last line without its line end was cut off while being written (a run killed, or stopped by a
    // full disk, mid-row): say so rather than blame the file's content.
    if (fields.size() != table.columns.size() && in.eof())
      throw InputError(
          fmt::format("{}:{}: the last row is torn (cut off while it was being written: a run killed or "
                      "stopped by a full disk); ibvalve run --restart rewrites it from a checkpoint",
                      path.string(), line_number));
    if (fields.size() != table.columns.size())
      throw InputError(fmt::format("{}:{}: expected {} values, found {}", path.string(), line_number,
                                   table.columns.size(), fields.size()));
    std::vector<double> row(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const char* begin = fields[i].data();
      const char* end = begin + fields[i].size();
      auto [ptr, ec] = std::from_chars(begin, end, row[i]);
      // The file may be any readable file (a path in a case file someone sent): the message names the
      // place and what was expected, never the text found there.
      if (ec != std::errc() || ptr != end)
        throw InputError(fmt::format(
            "{}:{}: expected a number in column {} of {} (a CSV table of numbers under a header row)",
            path.string(), line_number, i + 1, fields.size()));
    }
    table.rows.push_back(std::move(row));
  }
  if (!have_header) throw InputError(path.string() + ": empty file");
  return table;
}

} // namespace ibvalve::io
