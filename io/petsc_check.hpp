#pragma once
// Every PETSc call is checked. Inside functions that return PetscErrorCode use PETSc's own PetscCall;
// in C++ code that reports errors by exception use PETSC_CHECK (Debian's PETSc is built with the C
// language, so PETSc's PetscCallThrow is not available).
#include <fmt/format.h>
#include <stdexcept>
#include <string>

#include <petscsys.h>

namespace ibvalve {

/// Thrown when a PETSc call fails; the message names the call, the file and PETSc's own text.
class PetscFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] inline void throw_petsc_failure(PetscErrorCode code, const char* call, const char* file,
                                             int line)
{
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw PetscFailure(fmt::format("{}:{}: {} failed: {}", file, line, call,
                                 (text ? text : fmt::format("PETSc error {}", static_cast<int>(code)))));
}

} // namespace ibvalve

#define PETSC_CHECK(...)                                                                                     \
  do {                                                                                                       \
    const PetscErrorCode petsc_check_code_ = (__VA_ARGS__);                                                  \
    if (PetscUnlikely(petsc_check_code_))                                                                    \
      ::ibvalve::throw_petsc_failure(petsc_check_code_, #__VA_ARGS__, __FILE__, __LINE__);                   \
  } while (0)
