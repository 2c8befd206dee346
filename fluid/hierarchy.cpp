#include "fluid/hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <sstream>

#include "base/errors.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::fluid {

namespace {

PetscInt floor_div(PetscInt a, PetscInt b)
{
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
PetscInt ceil_div(PetscInt a, PetscInt b)
{
  return -floor_div(-a, b);
}

std::string describe(const IndexBox& b)
{
  std::ostringstream s;
  s << "cells [" << b.lower[0] << "," << b.upper[0] << ")x[" << b.lower[1] << "," << b.upper[1] << ")x["
    << b.lower[2] << "," << b.upper[2] << ")";
  return s.str();
}

} // namespace

PetscInt IndexBox::size() const
{
  return empty() ? 0 : cells(0) * cells(1) * cells(2);
}

bool IndexBox::contains(const Index3& c) const
{
  for (int d = 0; d < 3; ++d)
    if (c[d] < lower[d] || c[d] >= upper[d]) return false;
  return true;
}

bool IndexBox::contains(const IndexBox& o) const
{
  for (int d = 0; d < 3; ++d)
    if (o.lower[d] < lower[d] || o.upper[d] > upper[d]) return false;
  return true;
}

IndexBox IndexBox::grown(PetscInt n) const
{
  IndexBox b = *this;
  for (int d = 0; d < 3; ++d) {
    b.lower[d] -= n;
    b.upper[d] += n;
  }
  return b;
}

IndexBox IndexBox::intersection(const IndexBox& o) const
{
  IndexBox b;
  for (int d = 0; d < 3; ++d) {
    b.lower[d] = std::max(lower[d], o.lower[d]);
    b.upper[d] = std::max(b.lower[d], std::min(upper[d], o.upper[d]));
  }
  return b;
}

IndexBox IndexBox::refined(PetscInt r) const
{
  IndexBox b;
  for (int d = 0; d < 3; ++d) {
    b.lower[d] = lower[d] * r;
    b.upper[d] = upper[d] * r;
  }
  return b;
}

IndexBox IndexBox::coarsened(PetscInt r) const
{
  IndexBox b;
  for (int d = 0; d < 3; ++d) {
    b.lower[d] = floor_div(lower[d], r);
    b.upper[d] = ceil_div(upper[d], r);
  }
  return b;
}

GridHierarchy::GridHierarchy(const BoxGeometry& domain, std::vector<FinerLevel> finer_levels)
    : domain_(domain)
{
  Level base;
  base.ratio = 1;
  for (int d = 0; d < 3; ++d) base.h[d] = domain.spacing(d);
  base.domain_cells = domain.cells;
  base.boxes = {IndexBox{{0, 0, 0}, domain.cells}};
  levels_.push_back(base);

  for (std::size_t n = 0; n < finer_levels.size(); ++n) {
    const int l = static_cast<int>(n) + 1;
    const FinerLevel& spec = finer_levels[n];
    if (spec.ratio != 2 && spec.ratio != 4)
      throw HierarchyError(l, -1, fmt::format("refinement ratio must be 2 or 4, got {}", spec.ratio));
    if (spec.boxes.empty()) throw HierarchyError(l, -1, fmt::format("level {} has no boxes", l));
    Level level;
    level.ratio = spec.ratio;
    for (int d = 0; d < 3; ++d) {
      level.h[d] = levels_.back().h[d] / static_cast<double>(spec.ratio);
      level.domain_cells[d] = levels_.back().domain_cells[d] * spec.ratio;
    }
    level.boxes = spec.boxes;
    const IndexBox whole{{0, 0, 0}, level.domain_cells};
    for (std::size_t b = 0; b < spec.boxes.size(); ++b) {
      const IndexBox& box = spec.boxes[b];
      const int bi = static_cast<int>(b);
      if (box.empty()) throw HierarchyError(l, bi, "the box is empty (" + describe(box) + ")");
      if (!whole.contains(box))
        throw HierarchyError(
            l, bi, fmt::format("the box {} of level {} reaches outside the domain", describe(box), l));
      if (box.aligned_outward(spec.ratio) != box)
        throw HierarchyError(l, bi,
                             fmt::format("the box {} of level {} does not start and end on cells of level {}",
                                         describe(box), l, l - 1));
      for (std::size_t o = 0; o < b; ++o)
        if (!box.intersection(spec.boxes[o]).empty())
          throw HierarchyError(l, bi, fmt::format("the box overlaps box {} of level {}", o, l));
    }
    levels_.push_back(std::move(level));
    // Proper nesting: one coarser cell all around each box (inside the domain) belongs to the coarser level.
    const Level& coarser = levels_[l - 1];
    const IndexBox coarse_whole{{0, 0, 0}, coarser.domain_cells};
    for (std::size_t b = 0; b < spec.boxes.size(); ++b) {
      const IndexBox halo = spec.boxes[b].coarsened(spec.ratio).grown(1).intersection(coarse_whole);
      if (!covers(l - 1, halo))
        throw HierarchyError(l, static_cast<int>(b),
                             fmt::format("the box {} of level {} is not properly nested: level {} must cover "
                                         "it with one cell to spare on every side",
                                         describe(spec.boxes[b]), l, l - 1));
    }
  }
}

int GridHierarchy::box_containing(int level, const Index3& cell) const
{
  const auto& boxes = levels_[level].boxes;
  for (std::size_t b = 0; b < boxes.size(); ++b)
    if (boxes[b].contains(cell)) return static_cast<int>(b);
  return -1;
}

bool GridHierarchy::covered(int level, const Index3& cell) const
{
  if (level + 1 >= levels()) return false;
  const PetscInt r = ratio(level + 1);
  return box_containing(level + 1, {cell[0] * r, cell[1] * r, cell[2] * r}) >= 0;
}

PetscInt GridHierarchy::uncovered_cells(int level) const
{
  PetscInt n = 0;
  for (const IndexBox& box : boxes(level)) n += box.size();
  if (level + 1 < levels())
    for (const IndexBox& fine : boxes(level + 1)) n -= fine.coarsened(ratio(level + 1)).size();
  return n;
}

Real3 GridHierarchy::cell_center(int level, const Index3& c) const
{
  Real3 x;
  for (int d = 0; d < 3; ++d) x[d] = domain_.lower[d] + (static_cast<double>(c[d]) + 0.5) * h(level, d);
  return x;
}

IndexBox GridHierarchy::cells_overlapping(int level, const Real3& lower, const Real3& upper) const
{
  IndexBox b;
  for (int d = 0; d < 3; ++d) {
    b.lower[d] = static_cast<PetscInt>(std::floor((lower[d] - domain_.lower[d]) / h(level, d)));
    b.upper[d] = static_cast<PetscInt>(std::ceil((upper[d] - domain_.lower[d]) / h(level, d)));
    if (b.upper[d] == b.lower[d]) ++b.upper[d]; // a flat box still touches one layer of cells
  }
  return b.intersection(domain_box(level));
}

bool GridHierarchy::covers(int level, const IndexBox& region) const
{
  // The boxes of a level are disjoint, so the region is covered when the overlaps add up to its size.
  PetscInt inside = 0;
  for (const IndexBox& box : boxes(level)) inside += box.intersection(region).size();
  return inside == region.size();
}

// ---------------------------------------------------------------------------------------------------------
// Case-file keys.

void bind(io::KeyBinder& keys, NestedKeys& k)
{
  keys.integers("nested.ratios",
                "refinement ratio of each finer level to the one below it (2 or 4); "
                "[] = a single uniform level",
                k.ratios)
      .defaults(std::vector<std::int64_t>{})
      .sizes(0, 4)
      .at_least(2)
      .at_most(4);
  keys.integers("nested.margins",
                "automatic placement: cells of each finer level between the structure's bounding box (or "
                "the next finer level) and the level's edge; one value for every level or one per level",
                k.margins)
      .defaults(std::vector<std::int64_t>{4})
      .sizes(1, 4)
      .at_least(1)
      .at_most(4096);
  keys.tables("nested.box",
              "explicit boxes of the finer levels (a level without boxes is placed "
              "automatically around the structure)",
              k.boxes, [](io::KeyBinder& box, NestedBoxKeys& b) {
                box.integer("level", "the finer level (1 = first refined level) this box belongs to", b.level)
                    .required()
                    .at_least(1)
                    .at_most(4);
                box.reals("lower", "lower corner; on a corner of the next coarser level's cells", b.lower)
                    .unit("cm")
                    .required()
                    .size(3);
                box.reals("upper", "upper corner; on a corner of the next coarser level's cells", b.upper)
                    .unit("cm")
                    .required()
                    .size(3);
              });
}

namespace {

/// Spacing and whole-domain cells of every level, for converting corners.
struct LevelGrids {
  std::vector<Real3> h;
  std::vector<Index3> whole;
};

LevelGrids level_grids(const BoxGeometry& domain, const std::vector<std::int64_t>& ratios)
{
  const int finer = static_cast<int>(ratios.size());
  LevelGrids g{std::vector<Real3>(finer + 1), std::vector<Index3>(finer + 1)};
  for (int d = 0; d < 3; ++d) {
    g.h[0][d] = domain.spacing(d);
    g.whole[0][d] = domain.cells[d];
  }
  for (int l = 1; l <= finer; ++l)
    for (int d = 0; d < 3; ++d) {
      g.h[l][d] = g.h[l - 1][d] / static_cast<double>(ratios[l - 1]);
      g.whole[l][d] = g.whole[l - 1][d] * ratios[l - 1];
    }
  return g;
}

/// The [[nested.box]] entries as index boxes of their levels; `entry_of` the entry of each box.
void read_explicit_boxes(const io::KeyBinder& keys, const NestedKeys& k, const BoxGeometry& domain,
                         const LevelGrids& g, std::vector<FinerLevel>& levels,
                         std::vector<std::vector<std::size_t>>& entry_of)
{
  const int finer = static_cast<int>(k.ratios.size());
  for (std::size_t e = 0; e < k.boxes.size(); ++e) {
    const NestedBoxKeys& entry = k.boxes[e];
    if (entry.level > finer)
      keys.fail(entry.level, fmt::format("there are {} finer levels ({}), not {}", finer,
                                         keys.key_of(k.ratios), entry.level));
    const int l = static_cast<int>(entry.level);
    IndexBox box;
    for (const auto& [x, corner] :
         {std::pair{&entry.lower, &box.lower}, std::pair{&entry.upper, &box.upper}}) {
      for (int d = 0; d < 3; ++d) {
        // Corners lie on the coarser level's cell corners: (x - x0) / h_{l-1} is a whole number.
        const double q = ((*x)[d] - domain.lower[d]) / g.h[l - 1][d];
        const double n = std::round(q);
        if (std::abs(q - n) > 1e-8 * std::max(1.0, std::abs(q)))
          keys.fail(*x, fmt::format("not on a corner of the level-{} cells (spacing {:g} cm in direction {})",
                                    l - 1, g.h[l - 1][d], "xyz"[d]));
        if (n < 0 || n > static_cast<double>(g.whole[l - 1][d]))
          keys.fail(*x, std::string("outside the domain in direction ") + "xyz"[d]);
        (*corner)[d] = static_cast<PetscInt>(n) * k.ratios[l - 1];
      }
    }
    for (int d = 0; d < 3; ++d)
      if (box.upper[d] <= box.lower[d])
        keys.fail(entry.upper,
                  "must lie above " + keys.key_of(entry.lower) + " in direction " + std::string(1, "xyz"[d]));
    levels[l - 1].boxes.push_back(box);
    entry_of[l - 1].push_back(e);
  }
}

/// Automatic placement, finest first: each level without explicit boxes around the structure and the
/// next finer level's boxes, `margin(l)` cells to spare. The levels so placed are marked in `automatic`.
void place_automatic_levels(const io::KeyBinder& keys, const NestedKeys& k, const BoxGeometry& domain,
                            const LevelGrids& g, const std::optional<PhysicalBox>& structure,
                            const std::function<PetscInt(int)>& margin, std::vector<FinerLevel>& levels,
                            std::vector<bool>& automatic)
{
  const std::vector<std::int64_t>& ratios = k.ratios;
  const int finer = static_cast<int>(ratios.size());
  for (int l = finer; l >= 1; --l) {
    FinerLevel& level = levels[l - 1];
    level.ratio = ratios[l - 1];
    if (!level.boxes.empty()) continue;
    automatic[l - 1] = true;
    std::optional<IndexBox> hull;
    const auto add = [&](const IndexBox& b) {
      if (!hull) {
        hull = b;
        return;
      }
      for (int d = 0; d < 3; ++d) {
        hull->lower[d] = std::min(hull->lower[d], b.lower[d]);
        hull->upper[d] = std::max(hull->upper[d], b.upper[d]);
      }
    };
    if (structure) {
      IndexBox s;
      for (int d = 0; d < 3; ++d) {
        s.lower[d] = static_cast<PetscInt>(std::floor((structure->lower[d] - domain.lower[d]) / g.h[l][d]));
        s.upper[d] = static_cast<PetscInt>(std::ceil((structure->upper[d] - domain.lower[d]) / g.h[l][d]));
      }
      add(s.grown(margin(l)));
    }
    if (l < finer)
      for (const IndexBox& b : levels[l].boxes) add(b.coarsened(levels[l].ratio).grown(margin(l)));
    if (!hull)
      keys.fail(k.boxes, fmt::format("level {} has no [[{}]] and there is no structure to place it around", l,
                                     keys.key_of(k.boxes)));
    level.boxes = {hull->aligned_outward(level.ratio).intersection(IndexBox{{0, 0, 0}, g.whole[l]})};
  }
}

} // namespace

GridHierarchy read_hierarchy(const io::KeyBinder& keys, const NestedKeys& k, const BoxGeometry& domain,
                             const std::optional<PhysicalBox>& structure, const std::string& structure_key,
                             PetscInt support_cells)
{
  for (const auto r : k.ratios)
    if (r != 2 && r != 4) keys.fail(k.ratios, fmt::format("each ratio must be 2 or 4, got {}", r));
  const int finer = static_cast<int>(k.ratios.size());
  const auto& margins = k.margins;
  if (margins.size() != 1 && static_cast<int>(margins.size()) != finer)
    keys.fail(margins,
              fmt::format("give one margin or one per finer level ({}), got {}", finer, margins.size()));
  const auto margin = [&](int level) {
    return static_cast<PetscInt>(margins.size() == 1 ? margins[0] : margins[level - 1]);
  };
  const LevelGrids g = level_grids(domain, k.ratios);
  std::vector<FinerLevel> levels(finer);
  std::vector<std::vector<std::size_t>> entry_of(finer); // the [[nested.box]] index of each box
  read_explicit_boxes(keys, k, domain, g, levels, entry_of);
  std::vector<bool> automatic(finer, false);
  place_automatic_levels(keys, k, domain, g, structure, margin, levels, automatic);

  std::optional<GridHierarchy> hierarchy;
  try {
    hierarchy.emplace(domain, levels);
  } catch (const HierarchyError& e) {
    // An automatic level is the margins' doing; an explicit box is its entry's.
    const int level = e.level(), box = e.box();
    if (level < 1 || automatic[level - 1] || box < 0) keys.fail(margins, e.what());
    keys.fail(k.boxes[entry_of[level - 1][box]].lower, e.what());
  }

  if (structure && finer > 0) {
    const int f = hierarchy->finest();
    const IndexBox reach = hierarchy->cells_overlapping(f, structure->lower, structure->upper)
                               .grown(support_cells)
                               .intersection(hierarchy->domain_box(f));
    if (!hierarchy->covers(f, reach)) {
      const std::string message = fmt::format("the structure (bounding box with {} cells of kernel reach, {} "
                                              "of level {}) is not inside the finest level",
                                              support_cells, describe(reach), f);
      if (automatic[f - 1]) keys.fail(margins, message + "; raise the margin");
      keys.config().fail(structure_key,
                         fmt::format("{} (see [[{}]] with level = {})", message, keys.key_of(k.boxes), f));
    }
  }
  return std::move(*hierarchy);
}

} // namespace ibvalve::fluid
