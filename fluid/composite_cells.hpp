#pragma once
// The composite grid of nested levels (docs/nested.md): the cells of each level not covered by the next
// finer level, numbered level by level, box by box, x fastest; the rows of every composite operator are
// split over the ranks in that order (PETSc's default split).
#include <functional>
#include <vector>

#include "fluid/hierarchy.hpp"

namespace ibvalve::fluid {

/// The global numbering of the composite cells (the same on every rank).
class CompositeCells {
 public:
  explicit CompositeCells(const GridHierarchy& hierarchy);
  PetscInt size() const { return size_; }
  /// Composite index of `cell` of `level`, or -1 when it is covered or not on that level.
  PetscInt index(int level, const Index3& cell) const;
  struct Cell {
    int level;
    Index3 index;
  };
  /// Calls `visit(n, cell)` for every composite cell with n in [begin, end), in order.
  void for_each(PetscInt begin, PetscInt end, const std::function<void(PetscInt, const Cell&)>& visit) const;
  const GridHierarchy& hierarchy() const { return *hierarchy_; }

 private:
  const GridHierarchy* hierarchy_;
  PetscInt size_ = 0;
  std::vector<std::vector<std::vector<PetscInt>>> map_; // [level][box][offset in box] -> index or -1
};

} // namespace ibvalve::fluid
