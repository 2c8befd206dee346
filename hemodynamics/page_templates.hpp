#pragma once
// The Mustache templates that lay out ibvalve's pages: the run report (report.html.tpl, report.md.tpl)
// and the case comparison (comparison.html.tpl, comparison.md.tpl). They are built in
// (hemodynamics/templates/, embedded at build time, so no source tree is needed) and a user restyles a
// page by pointing it at a folder of their own copies (`--write-templates` writes the built-in ones).
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "hemodynamics/text_template.hpp"

namespace ibvalve::hemodynamics {

/// A built-in template: its file name and text.
struct TemplateFile {
  const char* name;
  const char* text;
};
/// Every built-in template (hemodynamics/templates/*.tpl).
std::span<const TemplateFile> builtin_templates();

/// Writes every built-in template into `folder` (created if needed) for a user to restyle; an existing
/// file there is an InputError (nothing is overwritten). Returns the files written.
std::vector<std::filesystem::path> write_builtin_templates(const std::filesystem::path& folder);

/// The two layouts of one page: <page>.html.tpl (values HTML-escaped) and <page>.md.tpl (values as they
/// are).
struct PageTemplates {
  TextTemplate html, markdown;
};

/// The templates of page `page` ("report", "comparison") from `folder`: either file may be missing, the
/// built-in one then serves; the built-in ones when `folder` is empty. An InputError naming `option`
/// (the key or option that gave the folder) for a folder that is missing or holds neither file, and one
/// naming the file and line for a template that does not parse.
PageTemplates load_page_templates(std::string_view page, const std::filesystem::path& folder,
                                  std::string_view option);

} // namespace ibvalve::hemodynamics
