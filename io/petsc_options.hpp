#pragma once
// Defaults in PETSc's options database that the user's options override: a solver tunes itself for
// its problem, and -<prefix><key> <value> on the command line still has the last word.
#include <string>

#include <petscsys.h>

#include "io/petsc_check.hpp"

namespace ibvalve::petsc {

/// Sets option `name` (with its leading '-') to `value` unless the database already has it. True when
/// it set it: the caller may clear it again (PetscOptionsClearValue) once its object has read it, so a
/// default for one solver does not outlive it.
inline bool set_option_unless_given(const std::string& name, const std::string& value)
{
  PetscBool given = PETSC_FALSE;
  PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &given));
  if (given) return false;
  PETSC_CHECK(PetscOptionsSetValue(nullptr, name.c_str(), value.c_str()));
  return true;
}

} // namespace ibvalve::petsc
