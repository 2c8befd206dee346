#pragma once
// What a fluid solver is told: the fluid's properties and how its equations are solved. One struct for
// both solvers (fluid::NavierStokes on one grid, fluid::NestedNavierStokes on nested levels); each reads
// the fields that apply to it and ignores the others.
#include <string>

#include <petscsys.h>

#include "fluid/convection.hpp"

namespace ibvalve::fluid {

/// One grid: the coupled Stokes solve by FFTs (every side periodic) or by preconditioned FGMRES.
enum class SolverKind { fft, krylov };
/// The sub-solves of the Krylov solver's projection preconditioner: one hypre BoomerAMG V-cycle each,
/// or the FFTW real-to-real transform solves (fluid/transform_subsolvers.hpp).
enum class SubsolverKind { amg, fft };
/// Nested levels: the pair of composite divergence and gradient (fluid/nested_navier_stokes.hpp).
enum class PressureCoupling { consistent, adjoint };

struct FluidSettings {
  double rho = 1.0; // g/cm^3
  double mu = 0.01; // dyn s/cm^2
  ConvectionScheme convection = ConvectionScheme::limited_upwind;
  /// Relative tolerance of every iterative solve of a step: the one-grid FGMRES, and on nested levels
  /// the viscous and the projection solves.
  double rtol = 1e-12;
  double atol = 1e-14;                                      // one grid: absolute tolerance of the FGMRES
  PetscInt max_iterations = 200;                            // one grid: most FGMRES iterations of a step
  SolverKind solver = SolverKind::fft;                      // one grid
  SubsolverKind subsolver = SubsolverKind::amg;             // one grid, Krylov solver
  PressureCoupling coupling = PressureCoupling::consistent; // nested levels
  /// Nested levels: the PETSc options prefix of the two solves (<prefix>velocity_, <prefix>pressure_).
  std::string nested_prefix = "nested_";
};

} // namespace ibvalve::fluid
