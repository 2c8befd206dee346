#include "fluid/composite_cells.hpp"

namespace ibvalve::fluid {

CompositeCells::CompositeCells(const GridHierarchy& hierarchy) : hierarchy_(&hierarchy)
{
  map_.resize(hierarchy.levels());
  for (int l = 0; l < hierarchy.levels(); ++l) {
    for (const IndexBox& box : hierarchy.boxes(l)) {
      std::vector<PetscInt> map(box.size(), -1);
      for (PetscInt k = box.lower[2]; k < box.upper[2]; ++k)
        for (PetscInt j = box.lower[1]; j < box.upper[1]; ++j)
          for (PetscInt i = box.lower[0]; i < box.upper[0]; ++i)
            if (!hierarchy.covered(l, {i, j, k})) map[box.offset({i, j, k})] = size_++;
      map_[l].push_back(std::move(map));
    }
  }
}

PetscInt CompositeCells::index(int level, const Index3& cell) const
{
  if (level < 0 || level >= hierarchy_->levels()) return -1;
  const int b = hierarchy_->box_containing(level, cell);
  if (b < 0) return -1;
  return map_[level][b][hierarchy_->boxes(level)[b].offset(cell)];
}

void CompositeCells::for_each(PetscInt begin, PetscInt end,
                              const std::function<void(PetscInt, const Cell&)>& visit) const
{
  for (int l = 0; l < hierarchy_->levels(); ++l) {
    const auto boxes = hierarchy_->boxes(l);
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      const IndexBox& box = boxes[b];
      const auto& map = map_[l][b];
      // Indices grow along each box, so a box whose range misses [begin, end) is skipped whole.
      PetscInt first = -1, last = -1;
      for (const PetscInt n : map)
        if (n >= 0) {
          if (first < 0) first = n;
          last = n;
        }
      if (first < 0 || last < begin || first >= end) continue;
      for (PetscInt k = box.lower[2]; k < box.upper[2]; ++k)
        for (PetscInt j = box.lower[1]; j < box.upper[1]; ++j)
          for (PetscInt i = box.lower[0]; i < box.upper[0]; ++i) {
            const PetscInt n = map[box.offset({i, j, k})];
            if (n >= begin && n < end) visit(n, Cell{l, {i, j, k}});
          }
    }
  }
}

} // namespace ibvalve::fluid
