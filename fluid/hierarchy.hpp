#pragma once
// A static hierarchy of nested Cartesian grid levels (docs/nested.md).
//
// Level 0 is the whole box of `BoxGeometry` (its cells). Level l >= 1 has spacing h_{l-1} / r_l with the
// refinement ratio r_l in {2, 4}, and covers the union of one or more disjoint index boxes given in its
// own cell indices (IndexBox: cells [lower, upper) of level l, counted from the box's lower corner).
// The rules (Berger & Colella 1989, J. Comput. Phys. 82:64, "proper nesting"):
//  - each box lies inside the domain and its corners are corners of level l-1 cells (alignment);
//  - boxes of one level do not overlap;
//  - each box of level l >= 2, coarsened to level l-1 and grown by one level-(l-1) cell (clipped to
//    the domain), is covered by the boxes of level l-1. So every coarse-fine face of level l has an
//    uncovered level-(l-1) cell on its coarse side, and so have that cell's tangential neighbours,
//    which the composite stencils of composite_poisson.hpp use.
// A composite cell is a cell of level l inside level l's boxes and not covered by level l+1.
// The hierarchy is the same on every rank (a few boxes); the data on it is split by the solvers.
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "fluid/grid.hpp"

namespace ibvalve::fluid {

/// Cells [lower, upper) of one level, in that level's global cell indices.
struct IndexBox {
  Index3 lower{0, 0, 0};
  Index3 upper{0, 0, 0};

  PetscInt cells(int d) const { return upper[d] - lower[d]; }
  PetscInt size() const;
  bool empty() const { return cells(0) <= 0 || cells(1) <= 0 || cells(2) <= 0; }
  bool contains(const Index3& cell) const;
  bool contains(const IndexBox& other) const;
  IndexBox grown(PetscInt n) const;
  IndexBox intersection(const IndexBox& other) const;
  /// The same region in the cells of a level `ratio` times finer.
  IndexBox refined(PetscInt ratio) const;
  /// The cells of a level `ratio` times coarser that overlap this box.
  IndexBox coarsened(PetscInt ratio) const;
  /// The smallest box made of whole cells of a level `ratio` times coarser that holds this box.
  IndexBox aligned_outward(PetscInt ratio) const { return coarsened(ratio).refined(ratio); }
  /// Position of `cell` inside the box, x fastest (0 .. size()-1).
  PetscInt offset(const Index3& cell) const
  {
    return ((cell[2] - lower[2]) * cells(1) + (cell[1] - lower[1])) * cells(0) + (cell[0] - lower[0]);
  }
  bool operator==(const IndexBox&) const = default;
};

/// A broken hierarchy rule: which finer level (>= 1) and box (-1: the level as a whole), and why.
class HierarchyError : public std::invalid_argument {
 public:
  HierarchyError(int level, int box, const std::string& message)
      : std::invalid_argument(message), level_(level), box_(box)
  {
  }
  int level() const { return level_; }
  int box() const { return box_; }

 private:
  int level_, box_;
};

/// The boxes of one finer level and its ratio to the next coarser level.
struct FinerLevel {
  PetscInt ratio = 2;
  std::vector<IndexBox> boxes;
};

class GridHierarchy {
 public:
  /// Checks every rule above; throws HierarchyError naming the first broken one.
  GridHierarchy(const BoxGeometry& domain, std::vector<FinerLevel> finer_levels);

  int levels() const { return static_cast<int>(levels_.size()); }
  int finest() const { return levels() - 1; }
  const BoxGeometry& domain() const { return domain_; }
  /// Ratio of level `level` to level-1 (1 for level 0).
  PetscInt ratio(int level) const { return levels_[level].ratio; }
  double h(int level, int d) const { return levels_[level].h[d]; }
  double cell_volume(int level) const { return h(level, 0) * h(level, 1) * h(level, 2); }
  /// Cells of the whole domain at this level's spacing.
  const Index3& domain_cells(int level) const { return levels_[level].domain_cells; }
  IndexBox domain_box(int level) const { return {{0, 0, 0}, domain_cells(level)}; }
  std::span<const IndexBox> boxes(int level) const { return levels_[level].boxes; }

  /// Index of the box of `level` holding `cell`, or -1.
  int box_containing(int level, const Index3& cell) const;
  /// True when `cell` of `level` lies under a box of level+1.
  bool covered(int level, const Index3& cell) const;
  /// Cells of `level` inside its boxes and not covered by level+1.
  PetscInt uncovered_cells(int level) const;
  Real3 cell_center(int level, const Index3& cell) const;
  /// The cells of `level` that overlap the physical box [lower, upper] (clipped to the domain).
  IndexBox cells_overlapping(int level, const Real3& lower, const Real3& upper) const;
  /// True when the union of the boxes of `level` covers `region` (cells of that level).
  bool covers(int level, const IndexBox& region) const;

 private:
  struct Level {
    PetscInt ratio = 1;
    Real3 h{};
    Index3 domain_cells{};
    std::vector<IndexBox> boxes;
  };
  BoxGeometry domain_;
  std::vector<Level> levels_;
};

/// A physical axis-aligned box (a structure's bounding box), in cm.
struct PhysicalBox {
  Real3 lower{};
  Real3 upper{};
};

} // namespace ibvalve::fluid

namespace ibvalve::io {
class KeyBinder;
} // namespace ibvalve::io

namespace ibvalve::fluid {

/// One [[nested.box]]: an explicit box of a finer level, its corners in cm.
struct NestedBoxKeys {
  std::int64_t level = 1;
  std::vector<double> lower, upper;
};

/// The case-file keys of the hierarchy (all under "nested."):
///   nested.ratios  = [4]        ratio of each finer level to the one below (2 or 4); [] = one level
///   nested.margins = [4]        automatic placement: cells of that level between the structure's bounding
///                               box (or the finer level) and the level's edge; one value, or one per level
///   [[nested.box]] level = 1, lower = [x, y, z], upper = [x, y, z]   (cm) explicit boxes of a level
/// A finer level without [[nested.box]] entries is placed around the structure's bounding box.
struct NestedKeys {
  std::vector<std::int64_t> ratios, margins;
  std::vector<NestedBoxKeys> boxes;
};

/// Declares (a Schema binder) or reads (a Config binder) the nested.* keys (io/key_binder.hpp).
void bind(io::KeyBinder& keys, NestedKeys& k);

/// Builds the hierarchy the keys `keys` read into `k` describe over `domain`. When `structure` is given, the
/// finest level must hold it with `support_cells` finest cells to spare (the IB kernel's reach), else the
/// error names `structure_key`. Every broken rule is one InputError "file:line: key: message".
GridHierarchy read_hierarchy(const io::KeyBinder& keys, const NestedKeys& k, const BoxGeometry& domain,
                             const std::optional<PhysicalBox>& structure = std::nullopt,
                             const std::string& structure_key = "structure", PetscInt support_cells = 2);

} // namespace ibvalve::fluid
