#pragma once
// Hyperelastic laws as StrainEnergy objects: the kernels of law_kernels.hpp turned into W, P = dW/dF
// and dP/dF at a material point, with the stress-free reference state made explicit.
//
// Stress-free reference state. The isotropic parts as written give P(I) = 2 dPsi/dI1(ref) I != 0
// (W1: 2 C10 C01 I; W2: 2 mu I; W3: 2 C1 I; neo-Hookean and HGO: mu I). In an incompressible model
// that stress is hydrostatic and goes into the Lagrange multiplier p. In the IB/FE setting the
// structure has no p of its own, so each law carries (by default) the pressure-like energy term
//     W_ref(F) = -2 d1_ref ln J,  d1_ref = dPsi/dI1 at C = I,
// whose stress -2 d1_ref F^{-T} cancels 2 d1_ref F at F = I exactly, and which is hydrostatic for
// every isochoric motion (J = 1), so it changes no deviatoric stress and no biaxial result. This is
// the stress-free correction used with the hybrid IB/FE method (Griffith & Luo 2017, Int. J. Numer.
// Meth. Biomed. Engng. 33:e2888; Vadala-Roth et al. 2020, CMAME 365:112978, "P = P_iso - 2 d1 F^{-T}").
// Written as an energy (not as a stress patch), W, P and dP/dF stay mutually consistent.
// The fiber terms need no correction: every law here has dPsi/dI4 = dPsi/dI6 = 0 at I4 = I6 = 1.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "materials/law_kernels.hpp"
#include "materials/strain_energy.hpp"

namespace ibvalve::materials {

/// Whether a fiber family under compression (I4 < 1) contributes: `excluded` ("off" in case files)
/// removes it, as in most valve work; `included` ("on") keeps the law as written.
enum class FiberCompression { excluded, included };

/// How P(I) = 0 is obtained (see the comment at the top of this file).
enum class ReferenceState {
  pressure_like, ///< adds -2 d1_ref ln J (default)
  as_written     ///< the law as written; P(I) = 2 d1_ref I (only for analysis, e.g. biaxial fits)
};

/// Which first invariant the isotropic part (and HGO's dispersion term) reads.
///  - `I1`: I1 = tr C, the law as the study writes it.
///  - `isochoric`: I1bar = J^{-2/3} tr C, the isochoric invariant of the decoupled (Flory) split used for
///    nearly incompressible solids with a separate volumetric penalty (Simo & Taylor 1991, CMAME
///    85:273; FEBio's "uncoupled" materials). For an incompressible tissue I1bar = I1, so the law, its
///    fits and every biaxial result are unchanged; the fiber invariant stays I4 = f0.C f0, as Nolan et
///    al. 2014 (J. Mech. Behav. Biomed. Mater. 39:48) recommend for anisotropic soft tissue (the
///    isochoric I4bar gives a fiber no stress under hydrostatic stretch). Where J departs from 1 the
///    isotropic energy grows without bound as a point is flattened (I1bar -> infinity as J -> 0 at a
///    bounded shape), so the tissue itself resists the collapse of an element corner that a penalty
///    integrated once per element leaves free (docs/fe.md, "Inverted element corners"). P(I) = 0
///    holds exactly, so no reference term is added.
enum class IsotropicInvariant { I1, isochoric };

struct LawOptions {
  FiberCompression fiber_compression = FiberCompression::excluded;
  ReferenceState reference_state = ReferenceState::pressure_like;
  IsotropicInvariant isotropic_invariant = IsotropicInvariant::I1;
};

struct ParameterInfo {
  std::string name;
  bool is_modulus = false; ///< a stress (kPa for users, dyn/cm^2 inside); otherwise dimensionless
  double upper = 1e300;    ///< upper bound (kappa <= 1/3); the lower bound is 0 for every parameter
  std::string doc;
};

struct LawInfo {
  LawKind kind;
  std::string name;    ///< as written in case files and on the command line
  std::string formula; ///< Psi in plain text
  /// Psi in the case file's formula syntax (law = "expression", docs/materials.md): the built-in kernel
  /// to round-off with the same options (hgo: with kappa = 0, or with fiber_compression = "on").
  std::string energy;
  std::vector<ParameterInfo> parameters;
  bool uses_second_family = false; ///< HGO reads FiberFrame::s0
};

const LawInfo& law_info(LawKind kind);
std::span<const LawInfo> all_laws();
std::optional<LawKind> find_law(std::string_view name);
/// "neo-hookean, W1, W2, W3, hgo".
std::string law_names();

/// One of the laws of law_kernels.hpp with its parameters (CGS: moduli in dyn/cm^2).
class InvariantLaw : public StrainEnergy {
 public:
  InvariantLaw(LawKind kind, std::vector<double> parameters, LawOptions options = {});

  std::string name() const override;
  double energy(const Mat3& F, const FiberFrame& fibers) const override;
  Mat3 stress(const Mat3& F, const FiberFrame& fibers) const override;
  Tangent tangent(const Mat3& F, const FiberFrame& fibers) const override;
  void stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const override;

  LawKind kind() const { return kind_; }
  std::span<const double> parameters() const { return parameters_; }
  const LawOptions& options() const { return options_; }
  /// dPsi/dI1 at C = I: the coefficient of the pressure-like reference term (0 with the isochoric
  /// invariant, which needs none).
  double reference_d1() const { return reference_d1_; }
  /// Psi and its invariant derivatives at F (without the reference term).
  InvariantResponse<double> invariants(const Mat3& F, const FiberFrame& fibers) const;
  /// P and dP/dF of Psi alone (without the reference term), for composites that add every
  /// volumetric term (reference and penalty) in one pass.
  Mat3 invariant_stress(const Mat3& F, const FiberFrame& fibers) const;
  void invariant_stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const;

 private:
  /// What the invariants and their derivatives need at F, computed once a call: C, tr C, the factor j
  /// of the isotropic invariant j tr C (J^{-2/3} with the isochoric invariant, else 1), F^{-T} (isochoric
  /// only) and d(j tr C)/dF.
  struct Kinematics {
    Mat3 C;
    double trace_C = 0.0;
    double j = 1.0;
    Mat3 H;
    Mat3 gradient;
  };
  Kinematics kinematics(const Mat3& F) const;
  InvariantResponse<double> invariants(const Kinematics& k, const FiberFrame& fibers) const;

  LawKind kind_;
  std::vector<double> parameters_;
  LawOptions options_;
  double reference_d1_ = 0.0;
};

/// The tangent of P = g(J) F^{-T} with g(J) = J U'(J): what every volumetric term adds
/// (`g_prime_J` = J g'(J) = J^2 U'' + J U').
void add_volumetric_tangent(const Mat3& F, double g, double g_prime_J, Tangent& T);
/// The same with H = F^{-T} already computed.
void add_volumetric_tangent_given_inverse(const Mat3& H, double g, double g_prime_J, Tangent& T);

} // namespace ibvalve::materials
