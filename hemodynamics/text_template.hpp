#pragma once
// A Mustache template (https://mustache.github.io/mustache.5.html), rendered by kainjow::mustache
// (libkainjow-mustache-dev): how the reports' HTML and Markdown are laid out, so that a user restyles
// them by editing a file, without recompiling.
//
// Lines holding nothing but one section, inverted-section, end or comment tag ("standalone" lines)
// leave no trace in the output, as the Mustache specification says. kainjow::mustache keeps the line
// break of such a line when its section is not rendered (an empty list, a false value) or when the
// tag is a comment, so the text is prepared before parsing: standalone lines lose their blanks and line
// break, and every other line starts with a marker that keeps the library's own, partial rule from
// removing it; the markers are taken out of the rendered text.
#include <string>
#include <string_view>

#include <kainjow/mustache.hpp>

namespace ibvalve::hemodynamics {

/// `text` made safe in a Markdown table cell: <, >, & and " as HTML entities (Markdown passes HTML
/// through, so a name from a user's files could open a tag), | as \| (it would end the cell) and line
/// breaks as blanks. How the Markdown templates insert {{name}}, and how pages written without a
/// template insert names.
std::string markdown_escaped(std::string_view text);

class TextTemplate {
 public:
  enum class Escaping {
    markdown, // {{name}} is made safe in a Markdown table: <, >, & as HTML entities, | as \|, line breaks
              // as blanks ({{{name}}} is not)
    html,     // {{name}} is made safe inside HTML ({{{name}}} is not)
  };
  /// Parses `text`; an InputError "origin: ..." (origin names the file) when it is no valid template.
  TextTemplate(std::string_view text, std::string origin, Escaping escaping);

  /// The text with `values` filled in; an InputError naming the origin when rendering fails.
  std::string render(const kainjow::mustache::data& values) const;

 private:
  std::string origin_;
  mutable kainjow::mustache::mustache template_;
};

} // namespace ibvalve::hemodynamics
