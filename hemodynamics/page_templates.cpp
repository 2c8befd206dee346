#include "hemodynamics/page_templates.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::hemodynamics {

namespace fs = std::filesystem;

std::vector<fs::path> write_builtin_templates(const fs::path& folder)
{
  std::vector<fs::path> files;
  for (const TemplateFile& t : builtin_templates()) {
    files.push_back(folder / t.name);
    if (fs::exists(files.back()))
      throw InputError(files.back().string() + ": exists (nothing was overwritten)");
  }
  io::create_output_folder(folder);
  for (std::size_t i = 0; i < files.size(); ++i)
    io::write_file_atomically(files[i], builtin_templates()[i].text);
  return files;
}

PageTemplates load_page_templates(std::string_view page, const fs::path& folder, std::string_view option)
{
  const std::string html_name = fmt::format("{}.html.tpl", page),
                    markdown_name = fmt::format("{}.md.tpl", page);
  auto builtin = [](const std::string& name) {
    for (const TemplateFile& t : builtin_templates())
      if (name == t.name) return t.text;
    throw std::logic_error("no built-in template " + name);
  };
  auto load = [&](const std::string& name, TextTemplate::Escaping escaping) {
    const fs::path file = folder / name;
    if (folder.empty() || !fs::exists(file)) return TextTemplate(builtin(name), "built-in " + name, escaping);
    return TextTemplate(io::read_text_file(file), file.string(), escaping);
  };
  if (!folder.empty()) {
    if (!fs::is_directory(folder))
      throw InputError(fmt::format("{}: {}: no such folder", folder.string(), option));
    if (!fs::exists(folder / html_name) && !fs::exists(folder / markdown_name))
      throw InputError(
          fmt::format("{}: {}: holds neither {} nor {}", folder.string(), option, html_name, markdown_name));
  }
  return {load(html_name, TextTemplate::Escaping::html),
          load(markdown_name, TextTemplate::Escaping::markdown)};
}

} // namespace ibvalve::hemodynamics
