#include "fluid/composite_output.hpp"

#include <fmt/format.h>

#include "io/petsc_check.hpp"
#include "io/petsc_handle.hpp"

namespace ibvalve::fluid {

std::vector<std::vector<std::vector<double>>> level_arrays(const CompositeCells& cells, Vec composite)
{
  // Gathered on rank 0: the composite vector of a study grid is small next to the fluid's state
  // (interim until the levels get distributed storage, docs/nested.md plan).
  petsc::OwnedVecScatter scatter;
  petsc::OwnedVec whole;
  PETSC_CHECK(VecScatterCreateToZero(composite, scatter.out(), whole.out()));
  PETSC_CHECK(VecScatterBegin(scatter, composite, whole, INSERT_VALUES, SCATTER_FORWARD));
  PETSC_CHECK(VecScatterEnd(scatter, composite, whole, INSERT_VALUES, SCATTER_FORWARD));
  PetscMPIInt rank = 0;
  MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(composite)), &rank);
  std::vector<std::vector<std::vector<double>>> out;
  if (rank == 0) {
    const GridHierarchy& h = cells.hierarchy();
    const PetscScalar* a = nullptr;
    PETSC_CHECK(VecGetArrayRead(whole, &a));
    out.resize(h.levels());
    for (int l = 0; l < h.levels(); ++l)
      for (const IndexBox& box : h.boxes(l)) out[l].emplace_back(box.size(), 0.0);
    cells.for_each(0, cells.size(), [&](PetscInt n, const CompositeCells::Cell& c) {
      const int b = h.box_containing(c.level, c.index);
      out[c.level][b][h.boxes(c.level)[b].offset(c.index)] = a[n];
    });
    PETSC_CHECK(VecRestoreArrayRead(whole, &a));
    // Restriction, finest first: each fine cell adds its share 1/r^3 to the coarse cell it lies in.
    for (int l = h.finest(); l >= 1; --l) {
      const PetscInt r = h.ratio(l);
      const double share = 1.0 / static_cast<double>(r * r * r);
      const auto boxes = h.boxes(l);
      for (std::size_t b = 0; b < boxes.size(); ++b) {
        const IndexBox& box = boxes[b];
        for (PetscInt k = box.lower[2]; k < box.upper[2]; ++k)
          for (PetscInt j = box.lower[1]; j < box.upper[1]; ++j)
            for (PetscInt i = box.lower[0]; i < box.upper[0]; ++i) {
              const Index3 coarse{i / r, j / r, k / r};
              const int cb = h.box_containing(l - 1, coarse);
              out[l - 1][cb][h.boxes(l - 1)[cb].offset(coarse)] += share * out[l][b][box.offset({i, j, k})];
            }
      }
    }
  }
  return out;
}

std::vector<io::XdmfGrid> write_composite_fields(io::Hdf5File& file, const CompositeCells& cells,
                                                 const std::vector<std::pair<std::string, Vec>>& fields,
                                                 const std::string& group, const std::string& file_reference,
                                                 const std::string& grid_prefix,
                                                 const std::vector<CompositeVectorField>& vector_fields,
                                                 const std::map<std::string, std::string>& units)
{
  const GridHierarchy& h = cells.hierarchy();
  std::vector<io::XdmfGrid> grids;
  for (int l = 0; l < h.levels(); ++l) {
    const auto boxes = h.boxes(l);
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      const IndexBox& box = boxes[b];
      const std::array<std::size_t, 3> n{static_cast<std::size_t>(box.cells(0)),
                                         static_cast<std::size_t>(box.cells(1)),
                                         static_cast<std::size_t>(box.cells(2))};
      std::array<double, 3> origin{};
      for (int d = 0; d < 3; ++d)
        origin[d] = h.domain().lower[d] + static_cast<double>(box.lower[d]) * h.h(l, d);
      grids.push_back(io::XdmfGrid::regular(fmt::format("{}level{}_box{}", grid_prefix, l, b), n, origin,
                                            {h.h(l, 0), h.h(l, 1), h.h(l, 2)}));
    }
  }
  // A scalar field is one component; a vector field's components are interleaved per cell (x fastest over
  // the cells, the component last), as ParaView reads a 3-vector.
  std::vector<std::pair<std::string, std::vector<Vec>>> all;
  for (const auto& [name, vec] : fields) all.push_back({name, {vec}});
  for (const auto& [name, components] : vector_fields)
    all.push_back({name, {components.begin(), components.end()}});
  for (const auto& [name, components] : all) {
    std::vector<std::vector<std::vector<std::vector<double>>>> arrays;
    for (Vec v : components) arrays.push_back(level_arrays(cells, v));
    const std::size_t m = components.size();
    const auto unit = units.find(name);
    const std::string field_units = unit == units.end() ? "" : unit->second;
    std::size_t g = 0;
    for (int l = 0; l < h.levels(); ++l) {
      const auto boxes = h.boxes(l);
      for (std::size_t b = 0; b < boxes.size(); ++b, ++g) {
        const IndexBox& box = boxes[b];
        std::vector<hsize_t> dims{static_cast<hsize_t>(box.cells(2)), static_cast<hsize_t>(box.cells(1)),
                                  static_cast<hsize_t>(box.cells(0))};
        if (m > 1) dims.push_back(m);
        std::vector<double> values;
        if (!arrays[0].empty()) { // rank 0
          const std::size_t n = arrays[0][l][b].size();
          values.resize(m * n);
          for (std::size_t c = 0; c < n; ++c)
            for (std::size_t d = 0; d < m; ++d) values[m * c + d] = arrays[d][l][b][c];
        }
        const std::string dataset = fmt::format("{}/level{}_box{}/{}", group, l, b, name);
        file.write_root(dataset, std::span<const double>(values), dims);
        if (!field_units.empty()) file.write_string_attribute(dataset, "units", field_units);
        grids[g].add_field(name, io::Center::cell, {dims.begin(), dims.end()},
                           file_reference + ":/" + dataset, field_units);
      }
    }
  }
  return grids;
}

} // namespace ibvalve::fluid
