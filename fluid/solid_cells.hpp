#pragma once
// Rigid walls inside the box, held by the fluid itself: the cells whose centre lies in a solid region
// (BoundaryConditions::solid) are blocked, the "obstacle cells" of the marker-and-cell method (Harlow &
// Welch 1965; Griebel, Dornseifer & Neunhoeffer 1998, "Numerical Simulation in Fluid Dynamics", section
// 3.3). Every face of a blocked cell holds u = 0 (an identity row of the Stokes system), the pressure of a
// blocked cell is decoupled (an identity row), and a fluid face whose tangential neighbour lies across a
// wall (both cells beyond it blocked) sees the wall half a cell away through the odd ghost u_g = -u_0.
// The wall is therefore a staircase of cell faces: exact in place for a wall along cell faces (second
// order in h there), first order in h for a curved wall. A wall the fluid holds imposes no explicit
// time-step limit, where an immersed elastic wall does (docs/fluid.md, "Walls inside the box").
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/grid.hpp"

namespace ibvalve::fluid {

/// A fluid face whose tangential neighbour in direction `e` (e != d) lies across a wall: the explicit
/// Laplacian's neighbour u_nb (0, a blocked face) becomes the ghost -u_0.
struct WallGhost {
  int d = 0;   // the face's component
  Index3 face; // the face's element index
  int e = 0;   // the direction of the wall
};

class SolidCells {
 public:
  /// No solid region in `bc`: empty() and every query false. Otherwise the owned blocked entries and the
  /// wall ghosts are listed once here, so that the steps do not evaluate the region again.
  SolidCells(const StaggeredGrid& grid, const BoundaryConditions& bc);

  bool empty() const { return !region_; }
  /// Whether cell idx (any index; outside a non-periodic box: false, periodic directions wrap) is blocked.
  bool cell(Index3 idx) const;
  /// Whether face (d, idx) touches a blocked cell: its velocity is held at 0.
  bool face(int d, const Index3& idx) const;
  /// Whether the neighbour of the fluid face (d, idx) in direction e (e != d), side `sign`, lies across
  /// a wall: both cells beside that neighbour face are blocked.
  bool wall_beyond(int d, const Index3& idx, int e, int sign) const;

  /// The owned fluid faces with a wall beyond a tangential neighbour, one entry per such neighbour.
  const std::vector<WallGhost>& wall_ghosts() const { return wall_ghosts_; }
  /// Sets the owned blocked faces of a local vector of this grid to 0 (a velocity state).
  void zero_faces(Vec local) const;
  /// Sets the owned blocked faces and cells of a local vector to 0 (a right side: their identity rows).
  void zero_rows(Vec local) const;

 private:
  /// Sets the entries at `offsets` (from the local array's first ghosted element) to 0.
  void zero(Vec local, const std::vector<PetscInt>& offsets) const;

  const StaggeredGrid& grid_;
  PointSet region_;
  std::vector<PetscInt> blocked_faces_, blocked_cells_; // owned entries, offsets in a local vector
  std::vector<WallGhost> wall_ghosts_;
};

} // namespace ibvalve::fluid
