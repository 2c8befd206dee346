#pragma once
// Composite cell fields on every level, for output and queries (docs/nested.md).
//
// A composite vector holds only uncovered cells; a level's box array also needs its covered cells, which
// hold the volume average of the finer cells over them (restriction, finest level first, so a cell covered
// by two finer levels holds the average of the finest data). One uniform XDMF grid per level box, so
// ParaView shows each level as a regular grid (hide or threshold the coarse levels to see the finest data).
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fluid/composite_poisson.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::fluid {

/// Every box of every level as a dense array (x fastest), covered cells averaged from the finer levels:
/// values[level][box][box.offset(cell)]. Collective; the arrays are returned on rank 0 only (empty
/// elsewhere).
std::vector<std::vector<std::vector<double>>> level_arrays(const CompositeCells& cells, Vec composite);

using CompositeVectorField = std::pair<std::string, std::array<Vec, 3>>;

/// Writes each field (a composite cell vector) as `group`/level<l>_box<b>/<name>, and each vector field
/// (three composite cell vectors, one per component) as one cells x 3 dataset there, and returns one XDMF
/// regular grid per level box, named "<grid_prefix>level<l>_box<b>"; `file_reference` is the HDF5 file as
/// the XDMF file names it. A field named in `units` gets them as its datasets' `units` attribute and in
/// its XDMF name ("pressure [dyn/cm^2]"). Collective.
std::vector<io::XdmfGrid> write_composite_fields(io::Hdf5File& file, const CompositeCells& cells,
                                                 const std::vector<std::pair<std::string, Vec>>& fields,
                                                 const std::string& group, const std::string& file_reference,
                                                 const std::string& grid_prefix = "",
                                                 const std::vector<CompositeVectorField>& vector_fields = {},
                                                 const std::map<std::string, std::string>& units = {});

} // namespace ibvalve::fluid
