#pragma once
// The PETSc options a case file may give (petsc.options): a case file is data a user may have been
// sent, so it may tune ibvalve's solvers and show what they do on the terminal, and nothing else.
// Options that read or write files, start programs or reach beyond ibvalve's solvers belong on the
// command line after `--`, which is the user's own and is not checked (docs/design.md, step 3).
#include <string>
#include <string_view>

#include "io/key_binder.hpp"

namespace ibvalve::app {

/// Why the PETSc options text `text` is not taken from a case file ("" when it is): the first option
/// refused, with the reason. The rules are an allow-list, read on PETSc's own split of the text:
///  - only letters, digits, blanks and `_ . + - ,`: PETSc splits at blanks and honours a double quote
///    only at a token's start, so with no quote, colon, slash, tab or line break the text splits one
///    way for PETSc and for this check;
///  - every option is -PREFIX SETTING with PREFIX one of ibvalve's solvers (fluid_stokes_, ...) and
///    SETTING one of a KSP, its preconditioner, their multigrid levels or sub-solvers, or the
///    factorization package (ksp_, pc_, mg_, sub_, mat_), or one of ibvalve's own options;
///  - a setting that shows something (view, monitor, converged_reason) takes no value, so it prints
///    to the terminal (a value is a viewer: a file, a drawing, a socket);
///  - none names python, draw, _lg, save, dump or file (Python code, windows, files).
std::string refused_case_petsc_options(std::string_view text);

/// Throws the input error "FILE:LINE: petsc.options: -OPTION: why; ..." for refused options: `options` is
/// the text `keys` read from the case's petsc.options.
void check_case_petsc_options(const io::KeyBinder& keys, const std::string& options);

} // namespace ibvalve::app
