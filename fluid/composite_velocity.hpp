#pragma once
// The staggered (MAC) velocity on the composite grid of a GridHierarchy (docs/nested.md, "Velocity on the
// levels").
//
// Unknowns: the composite faces of CompositeOperators (built with CompositeBoundary::neumann or `mixed`),
// i.e. the normal velocity on every face between two uncovered cells of one level, on every fine face of a
// coarse-fine interface, and on the boundary faces where the operators have a Dirichlet (pressure) face:
// the traction sides of an open box. Wall faces carry the given normal velocity (zero). Every other
// face value a stencil needs is an affine combination of the unknowns and of wall data (a `FaceValue`):
//  - a face under a finer level ("covered", or a coarse face on a coarse-fine interface): tensor-product
//    quadratic interpolation of the finer level's face values at the coarse face's centre, from finer
//    faces inside the finer level only (so the coarse stencils see the fine solution, error O(h^3));
//  - a face outside its level's boxes (a fine ghost): tensor-product quadratic interpolation of the coarser
//    level's faces (which may themselves be covered: then they are fine data), error O(H^3);
//  - a tangential-velocity ghost half a cell outside a side: quadratic extrapolation through the wall
//    value, g_ghost = (8 g - 6 u_1 + u_2)/3 (g = 0 on traction sides);
//  - a normal-velocity ghost beyond a traction face: even about the side (du_n/dn = 0, fluid/boundary.hpp).
// A ghost error O(h^3) makes the truncation error of the 7-point Laplacian O(h) on the layer of faces next
// to a coarse-fine interface and O(h^2) elsewhere, which keeps the solution second order (the quadratic
// coarse-fine interpolation of Martin & Colella 2000, J. Comput. Phys. 163:271, and Minion 1996,
// J. Comput. Phys. 127:158, here written as one point interpolation per ghost).
//
// The viscous operator L (each component's 7-point Laplacian on the composite faces, ghosts as above) is
// an assembled PETSc matrix plus a wall-data part; the convective term N(u) = div(u u) is the conservative
// MAC form (limited upwind-biased or centred face values) evaluated level by level with the same ghosts.
// Neither is refluxed at coarse-fine interfaces (momentum is conserved there to truncation error); mass is
// conserved exactly by the projection (fluid/nested_navier_stokes.hpp).
//
// The ghost maps are replicated on every rank (like CompositeCells): convection gathers the whole
// composite velocity on each rank (interim, see docs/nested.md) and reads its ghost values from a
// FaceValueTable made once.
#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include <petscmat.h>

#include "fluid/boundary.hpp"
#include "fluid/composite_poisson.hpp"
#include "fluid/convection.hpp"

namespace ibvalve::fluid {

/// The face normal to `normal` between cells index - e_normal and index of `level`.
struct FaceKey {
  int level = 0;
  int normal = 0;
  Index3 index{};
};

/// An affine combination of composite face unknowns and wall data points.
struct FaceValue {
  std::vector<std::pair<PetscInt, double>> unknowns;
  std::vector<std::pair<PetscInt, double>> data;
  void add(const FaceValue& other, double weight);
  /// Sorts the terms and merges repeated indices.
  void compress();
};

/// A list of FaceValues flattened for evaluation in one pass (compressed rows of unknown and data terms),
/// so that a step's many evaluations read two contiguous arrays instead of chasing a FaceValue each. A
/// null entry evaluates to zero. The terms are summed in the FaceValue's order (unknowns, then data),
/// so the result equals CompositeVelocity::evaluate bit for bit.
class FaceValueTable {
 public:
  FaceValueTable() = default;
  explicit FaceValueTable(std::span<const FaceValue* const> values);
  std::size_t size() const { return unknown_begin_.empty() ? 0 : unknown_begin_.size() - 1; }
  /// out[i] = value i for the whole face vector `all` (every rank's copy) and the wall data.
  void evaluate(std::span<const double> all, std::span<const double> data, std::span<double> out) const;

 private:
  std::vector<std::size_t> unknown_begin_, data_begin_;
  std::vector<PetscInt> unknown_index_, data_index_;
  std::vector<double> unknown_weight_, data_weight_;
};

/// Candidate windows of consecutive sample indices in [0, top] for interpolating at position s (in sample
/// units): the centred three, the other three holding s, three shifted inside [0, top], two, one; best first.
std::vector<std::vector<PetscInt>> sample_windows(double s, PetscInt top);

class CompositeVelocity {
 public:
  enum class Kind { unknown, wall, covered, outside_level, outside_domain };
  /// `operators` gives the face numbering; built with CompositeBoundary::neumann (closed box) or `mixed`
  /// (its Dirichlet faces are the traction faces).
  explicit CompositeVelocity(const CompositeOperators& operators);
  CompositeVelocity(const CompositeVelocity&) = delete;
  CompositeVelocity& operator=(const CompositeVelocity&) = delete;

  const CompositeOperators& operators() const { return *operators_; }
  const GridHierarchy& hierarchy() const { return operators_->cells().hierarchy(); }

  Kind classify(const FaceKey& key) const;
  /// Global index of an unknown face, -1 otherwise.
  PetscInt index(const FaceKey& key) const;
  Real3 position(const FaceKey& key) const;
  /// The face's value as an affine combination (memoised; references stay valid).
  const FaceValue& value(const FaceKey& key) const;
  /// Keys of the faces this rank owns, in the order of the face vector's owned entries.
  const std::vector<FaceKey>& owned_keys() const { return owned_keys_; }

  /// Wall data points (position, velocity component) and their values for a wall velocity at time t.
  struct DataPoint {
    Real3 x{};
    int component = 0;
  };
  const std::vector<DataPoint>& data_points() const { return data_points_; }
  std::vector<double> data_values(const VelocityFunction& wall_velocity, double t) const;

  /// L: the composite face Laplacian of the unknowns; the full operator is L u + b(g) (laplacian_data).
  Mat laplacian() const { return laplacian_.get(); }
  /// out = b(g): the wall-data part of the Laplacian on the owned faces.
  void laplacian_data(const std::vector<double>& data, Vec out) const;
  /// out = N(u) = div(u u) (conservative on each level) on the owned faces; u a face vector. The advected
  /// velocity on a momentum-cell side is the centred average or the limited upwind-biased reconstruction
  /// of fluid/convection.hpp (`limited_face_value`), from the same ghost values.
  void convection(Vec u, const std::vector<double>& data, Vec out,
                  ConvectionScheme scheme = ConvectionScheme::centered) const;
  /// The cell-centred velocity of each composite cell, component d the mean of the cell's two d-normal
  /// faces (unknowns, walls or coarse-fine ghosts as value() gives them) on the cell's own level: for
  /// output (the second-order cell average of the MAC field, as on one level). `out[d]` are composite
  /// cell vectors (CompositeOperators::create_cell_vector). Collective.
  void cell_velocity(Vec u, const VelocityFunction& wall_velocity, double t,
                     const std::array<Vec, 3>& out) const;
  /// Every rank's copy of the whole face vector `u` (collective).
  std::vector<double> gather(Vec u) const;
  /// out = `table` evaluated for the face vector `u` (gathered from every rank into a vector kept for the
  /// purpose, read in place) and the wall data. Collective.
  void evaluate(const FaceValueTable& table, Vec u, std::span<const double> data,
                std::span<double> out) const;
  /// Evaluates a FaceValue against a gathered vector and wall data.
  static double evaluate(const FaceValue& value, const std::vector<double>& all,
                         const std::vector<double>& data);

 private:
  enum class Mode { finer_interior, coarser };
  // The constructor's steps, in its order.
  /// Replays CompositeOperators' face numbering on every rank (indices_); returns the number of faces.
  PetscInt number_faces();
  /// The keys of the faces this rank owns (owned_keys_), in the operators' order and checked against
  /// their face centres; returns the global index of the first.
  PetscInt find_owned_keys(PetscInt faces);
  /// The composite face Laplacian of the owned faces (laplacian_, laplacian_data_); `begin` as above.
  void assemble_laplacian(PetscInt begin);
  /// The face values convection reads and each owned face's 24 positions among them.
  void build_convection_stencils();
  FaceValue compute(const FaceKey& key) const;
  FaceValue interpolate(int level, int normal, const Real3& x, Mode mode) const;
  PetscInt data_point(const Real3& x, int component) const;

  const CompositeOperators* operators_;
  std::unordered_map<std::uint64_t, PetscInt> indices_;
  mutable std::unordered_map<std::uint64_t, FaceValue> values_;
  mutable std::vector<DataPoint> data_points_;
  mutable std::unordered_map<std::uint64_t, PetscInt> data_index_;
  std::vector<FaceKey> owned_keys_;
  petsc::OwnedMat laplacian_;
  std::vector<std::vector<std::pair<PetscInt, double>>> laplacian_data_;
  // Convection: the face values it reads, and for each owned face the 24 positions among them it reads.
  FaceValueTable convection_values_;
  std::vector<std::array<std::int32_t, 24>> convection_stencils_;
  mutable std::vector<double> convection_buffer_; // the values of convection_values_, made once
  petsc::OwnedVecScatter gather_;
  petsc::OwnedVec gathered_;
};

} // namespace ibvalve::fluid
