#pragma once
// Field snapshots of an IB/FE run (the ibfe and aortic-valve models, on one level or nested levels): one
// HDF5 file per snapshot, <run>/fields/step_<n>.h5, with the fluid's fields (each rank writes its block)
// and the structure's current mesh with its displacement, velocity, J, fiber strain, the Cauchy stress
// along the fiber, fiber directions and part ids, plus one entry in each of <run>/fields_fluid.xdmf and
// <run>/fields_structure.xdmf, which ParaView ("Xdmf3 Reader") opens as two datasets. Units are in each
// dataset's `units` attribute and in the XDMF names (CGS, and the stress in kPa as the report gives it).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <mpi.h>

#include "app/step_diagnostics.hpp"
#include "app/time_loop.hpp"
#include "fe/mesh.hpp"
#include "fluid/flow_solver.hpp"
#include "ib/ibfe.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

namespace ibvalve::app {

/// "fields/step_<n>.h5": the snapshot file of step n, relative to the run folder.
std::string fields_file_name(long step);

/// The structure's part id of every element: 1 + the index of its body part in the solid (the
/// aortic valve: leaflet1-3 = 1-3, tube = 4), 0 for an element in no part.
std::vector<std::int64_t> structure_part_ids(const fe::SolidModel& solid);
/// "1 = leaflet1, 2 = leaflet2, ...": the ids' names, as the field files state them.
std::string structure_part_table(const fe::SolidModel& solid);

/// Writes the structure's mesh/* datasets into `h5` (rank 0 writes; collective) and returns their XDMF
/// grid; `file` is the HDF5 file as the XDMF file names it. The geometry is the current positions;
/// every real dataset has a `units` attribute; `part` (int64 per element) names its ids in its
/// `parts` attribute and in the grid's Information "part". The nodes' velocity is `structure_velocity`,
/// a name apart from the fluid's cell `velocity`.
io::XdmfGrid write_structure_fields(io::Hdf5File& h5, const fe::Mesh& mesh, const ib::IbfeIntegrator& ibfe,
                                    const std::string& file);

/// The parts of an IB/FE run's field snapshots, each with its series (TimeLoop::field_parts).
inline const std::vector<std::string> ibfe_field_parts{"fluid", "structure"};

/// Writes the snapshot of step `step` and adds it to the series (collective): the fluid's fields
/// (FlowSolver::write_fields: one grid, or every level box of nested levels) to series "fluid", the
/// structure's to series "structure".
void write_ibfe_fields(MPI_Comm comm, const std::filesystem::path& directory, FieldSeries& series,
                       const fe::Mesh& mesh, const fluid::FlowSolver& fluid, const ib::IbfeIntegrator& ibfe,
                       long step);

/// Watches the structure's smallest quadrature-point J step by step and warns (rank 0, log.txt too) on
/// each step where it goes from above zero to zero or below: an inverted element corner, after which a
/// run usually blows up within some steps (docs/fe.md, "Inverted element corners"). The warning names
/// the time, J, the element, its body part and where the element sits in the reference mesh.
class InversionWatch {
 public:
  /// Keeps a reference to `solid`, which must outlive the watch.
  explicit InversionWatch(const fe::SolidModel& solid) : solid_(solid) {}
  void observe(double t, const fe::SmallestJacobian& smallest);

 private:
  const fe::SolidModel& solid_;
  bool inverted_ = false;
};

/// The figures of a coupled step: the fluid's (fluid_step_figures), the structure's projection
/// iterations (0 for the default direct solves) and its smallest quadrature-point J
/// (fe::SolidModel::smallest_point_jacobian; column smallest_J, "min J" on the progress line), which
/// `watch`, when given, observes. Collective.
StepFigures ibfe_step_figures(const fluid::FlowSolver& fluid, const ib::IbfeIntegrator& ibfe, double dt,
                              InversionWatch* watch = nullptr);

/// The hooks every IB/FE run gives the time loop (app/time_loop.hpp): the time, the field snapshots, a
/// checkpoint of the fluid (`fluid/`, first: restoring it refills what the structure reads) and the
/// structure (`ibfe/`), the FFTW plans beside each checkpoint, and the step's figures. A model with more
/// state wraps save and restore. The figures carry an InversionWatch. `context`, `mesh`, `fluid` and `ibfe`
/// must outlive the loop's run.
void set_ibfe_hooks(TimeLoop& loop, const RunContext& context, const fe::Mesh& mesh, fluid::FlowSolver& fluid,
                    ib::IbfeIntegrator& ibfe, double dt);

/// The closing lines of an IB/FE run's summary: time per coupled step and its parts (then `after_parts`,
/// e.g. solver iterations), the structure's volume change from `initial_volume`, and where the fields
/// (`outputs` snapshots, fields_fluid.xdmf and fields_structure.xdmf) and the time series are.
std::vector<std::string> ibfe_summary_lines(const ib::IbfeIntegrator& ibfe, double initial_volume,
                                            const std::filesystem::path& directory, std::size_t outputs,
                                            const std::string& after_parts = "");

} // namespace ibvalve::app
