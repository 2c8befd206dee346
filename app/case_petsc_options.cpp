#include "app/case_petsc_options.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <span>
#include <vector>

#include <fmt/format.h>

namespace ibvalve::app {

namespace {

/// The options prefixes of ibvalve's solvers (KSPSetOptionsPrefix in fluid/, ib/, fibers/; the list
/// `ibvalve run --help` prints).
constexpr std::array<std::string_view, 8> solver_prefixes{
    "fluid_stokes_",    "fluid_helmholtz_",  "fluid_poisson_", "nested_pressure_",
    "nested_velocity_", "ib_velocity_mass_", "ib_force_mass_", "fibers_"};
/// What may follow a prefix: a KSP, its preconditioner, multigrid levels and block sub-solvers, the
/// factorization package of a direct solve.
constexpr std::array<std::string_view, 5> setting_stems{"ksp_", "pc_", "mg_", "sub_", "mat_"};
/// ibvalve's own options (fluid/fft_stokes.cpp, krylov_stokes.cpp, transform_subsolvers.cpp,
/// nested_navier_stokes.cpp).
constexpr std::array<std::string_view, 4> own_options{"fluid_fftw_planner", "fluid_helmholtz_jacobi_limit",
                                                      "fluid_poisson_capacitance",
                                                      "nested_pressure_composite_multigrid"};
/// Settings that show something: their value, if any, is a PETSc viewer (a file, a drawing, a socket).
constexpr std::array<std::string_view, 3> showing{"view", "monitor", "converged_reason"};
/// Parts of a name that run Python code, open windows or name files.
constexpr std::array<std::string_view, 6> never{"python", "draw", "_lg", "save", "dump", "file"};

bool allowed_character(char c)
{
  return std::isalnum(static_cast<unsigned char>(c)) || c == ' ' || c == '_' || c == '.' || c == '+' ||
         c == '-' || c == ',';
}

bool contains_any(std::string_view name, std::span<const std::string_view> parts)
{
  return std::any_of(parts.begin(), parts.end(),
                     [&](std::string_view part) { return name.find(part) != std::string_view::npos; });
}

/// Why the option `name` (without its '-', lower case) with `value` ("" for none) is refused.
std::string refused_option(std::string_view name, std::string_view value)
{
  const bool own = std::find(own_options.begin(), own_options.end(), name) != own_options.end();
  const auto prefix = std::find_if(solver_prefixes.begin(), solver_prefixes.end(),
                                   [&](std::string_view p) { return name.starts_with(p); });
  const std::string_view setting = prefix == solver_prefixes.end() ? name : name.substr(prefix->size());
  const bool solver_setting = prefix != solver_prefixes.end() &&
                              std::any_of(setting_stems.begin(), setting_stems.end(),
                                          [&](std::string_view s) { return setting.starts_with(s); });
  if (!own && !solver_setting) {
    std::string prefixes;
    for (std::string_view p : solver_prefixes)
      prefixes += fmt::format("{}-{}", prefixes.empty() ? "" : ", ", p);
    return "not a setting of ibvalve's solvers (a case file takes -PREFIX followed by ksp_, pc_, mg_, "
           "sub_ or mat_, with PREFIX one of " +
           prefixes + ")";
  }
  if (contains_any(name, never) || contains_any(value, never))
    return "runs Python code, opens a window or names a file";
  if (!value.empty() && contains_any(name, showing))
    return "a value here is a PETSc viewer (a file, a drawing, a socket); without one it prints to the "
           "terminal";
  return "";
}

} // namespace

std::string refused_case_petsc_options(std::string_view text)
{
  // PETSc's split (PetscOptionsInsertString): tokens between blanks; a token starting with '-' and not
  // a number is an option, the next token its value unless that is an option too.
  std::vector<std::string> tokens;
  std::string token;
  for (char c : std::string(text) + ' ') {
    if (c != ' ') {
      token += c;
    } else if (!token.empty()) {
      tokens.push_back(token);
      token.clear();
    }
  }
  auto is_option = [](const std::string& t) {
    return t.size() > 1 && t[0] == '-' && !std::isdigit(static_cast<unsigned char>(t[1])) && t[1] != '.';
  };
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const bool option = is_option(tokens[i]);
    // The option a token belongs to names it in the message: an option itself, or the one before a value.
    std::string shown = option || i == 0 || !is_option(tokens[i - 1]) ? tokens[i] : tokens[i - 1];
    shown = shown.substr(
        0, std::min<std::size_t>(60, std::find_if_not(shown.begin(), shown.end(), allowed_character) -
                                         shown.begin()));
    const auto bad = std::find_if_not(tokens[i].begin(), tokens[i].end(), allowed_character);
    if (bad != tokens[i].end()) {
      const unsigned char c = static_cast<unsigned char>(*bad);
      const std::string what = std::isprint(c) ? fmt::format("'{}'", static_cast<char>(c))
                                               : fmt::format("the byte 0x{:02x}", static_cast<unsigned>(c));
      return fmt::format("{}: {} is not allowed (options and values hold letters, digits and _ . + - , "
                         "separated by blanks: PETSc would split the text otherwise than it reads)",
                         shown, what);
    }
    if (!option) {
      if (i == 0 || !is_option(tokens[i - 1]))
        return fmt::format("{}: expected an option (-NAME), or a value after one", shown);
      continue;
    }
    std::string name = tokens[i].substr(1);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const std::string value = i + 1 < tokens.size() && !is_option(tokens[i + 1]) ? tokens[i + 1] : "";
    const std::string why = refused_option(name, value);
    if (!why.empty()) return fmt::format("-{}{}: {}", name, value.empty() ? "" : " " + value, why);
  }
  return "";
}

void check_case_petsc_options(const io::KeyBinder& keys, const std::string& options)
{
  const std::string why = refused_case_petsc_options(options);
  if (!why.empty())
    keys.fail(options, why + "; not taken from a case file (give it on the command line after --)");
}

} // namespace ibvalve::app
