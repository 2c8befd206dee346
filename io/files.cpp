#include "io/files.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

#include "io/errors.hpp"

namespace ibvalve::io {

void write_file_atomically(const std::filesystem::path& path, std::string_view content)
{
  const std::filesystem::path temporary = path.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + temporary.string() + ": " + std::strerror(errno));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + temporary.string() + ": " + std::strerror(errno));
  }
  std::filesystem::rename(temporary, path);
}

std::string read_text_file(const std::filesystem::path& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot be read");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

CsvWriter::CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns, bool append,
                     const std::vector<std::string>& units)
    : columns_(std::move(columns))
{
  if (!units.empty() && units.size() != columns_.size())
    throw std::logic_error("CsvWriter: " + std::to_string(units.size()) + " units for " +
                           std::to_string(columns_.size()) + " columns of " + path.string());
  const bool exists = append && std::filesystem::exists(path);
  out_.open(path, exists ? std::ios::app : std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + path.string());
  out_.precision(12);
  if (!exists) {
    for (std::size_t i = 0; i < columns_.size(); ++i) out_ << (i ? "," : "") << columns_[i];
    out_ << "\n";
    // A continued run appends to the file as it is: an older series without this line stays without.
    if (!units.empty()) {
      out_ << "# units: ";
      for (std::size_t i = 0; i < units.size(); ++i) out_ << (i ? "," : "") << units[i];
      out_ << "\n";
    }
    out_.flush();
  }
}

void CsvWriter::write_row(const std::vector<double>& values)
{
  for (std::size_t i = 0; i < values.size(); ++i) out_ << (i ? "," : "") << values[i];
  out_ << "\n";
  out_.flush();
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

CsvTable read_csv(const std::filesystem::path& path, bool header)
{
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
      table.columns = fields;
      have_header = true;
      continue;
    }
    if (table.columns.empty())
      for (std::size_t i = 0; i < fields.size(); ++i) table.columns.push_back("c" + std::to_string(i));
    if (fields.size() != table.columns.size())
      throw InputError(path.string() + ":" + std::to_string(line_number) + ": expected " +
                       std::to_string(table.columns.size()) + " values, found " +
                       std::to_string(fields.size()));
    std::vector<double> row(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const char* begin = fields[i].data();
      const char* end = begin + fields[i].size();
      auto [ptr, ec] = std::from_chars(begin, end, row[i]);
      // The file may be any readable file (a path in a case file someone sent): the message names the
      // place and what was expected, never the text found there.
      if (ec != std::errc() || ptr != end)
        throw InputError(path.string() + ":" + std::to_string(line_number) +
                         ": expected a number in column " + std::to_string(i + 1) + " of " +
                         std::to_string(fields.size()) + " (a CSV table of numbers under a header row)");
    }
    table.rows.push_back(std::move(row));
  }
  if (!have_header) throw InputError(path.string() + ": empty file");
  return table;
}

} // namespace ibvalve::io
