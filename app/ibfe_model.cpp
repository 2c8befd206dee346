// `model = "ibfe"`: an elastic structure (a finite-element mesh) immersed in viscous incompressible
// fluid on a staggered grid, coupled by the IB/FE method (ib/ibfe.hpp; docs/ib.md). The structure is
// read from a Gmsh file or generated (a box of hexahedra, a thick spherical shell), may start from a
// stretched or inflated configuration, and may be tethered. Output: fields/*.h5 + fields.xdmf with
// the grid's velocity, vorticity and pressure and the mesh's displacement, velocity, J, fiber strain
// and fiber stress side by side (one ParaView state opens both), and timeseries.csv.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <mpi.h>

#include "app/fftw_plans.hpp"
#include "app/fluid_box.hpp"
#include "app/ibfe_fields.hpp"
#include "app/model.hpp"
#include "app/resource_estimate.hpp"
#include "app/structure_levels.hpp"
#include "app/structure_parts.hpp"
#include "app/time_loop.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fluid/flow_solver.hpp"
#include "fluid/hierarchy.hpp"
#include "ib/eulerian_fluid.hpp"
#include "ib/ibfe.hpp"
#include "fe/shell_mesh.hpp"
#include "io/checkpoint.hpp"
#include "base/errors.hpp"
#include "io/files.hpp"
#include "io/hdf5.hpp"
#include "base/logger.hpp"
#include "io/xdmf.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

namespace {

void add_ibfe_schema(io::Schema& s)
{
  s.add_real("time.end", "simulated time").unit("s").defaults(0.05).positive();
  s.add_real("time.step", "time step of the coupled scheme (see the stability estimate in the log)")
      .unit("s")
      .defaults(1e-3)
      .positive();
  s.add_integer("output.every", "write fields every this many steps (and the first and last)")
      .defaults(std::int64_t{10})
      .at_least(1);
  add_fluid_density_key(s, "fluid density");
  add_fluid_viscosity_key(s, 4.0);
  s.add_integer_list("fluid.cells", "grid cells in x, y, z")
      .size(3)
      .at_most(max_grid_cells)
      .defaults(std::vector<std::int64_t>{32, 32, 32});
  s.add_real_list("fluid.lower", "lower corner of the box")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0, 0, 0});
  s.add_real_list("fluid.upper", "upper corner of the box")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{1, 1, 1});
  s.add_string("fluid.boundary", "periodic box (FFT solver) or no-slip walls on every side (Krylov solver)")
      .choices({"periodic", "walls"})
      .defaults(std::string("periodic"));

  s.add_string("structure.shape",
               "where the mesh comes from: a Gmsh file, a generated box or spherical shell")
      .choices({"file", "box", "spherical-shell"})
      .defaults(std::string("box"));
  s.add_string("structure.mesh", "Gmsh mesh (.msh) of hexahedra or tetrahedra, when shape = \"file\"")
      .file(true);
  s.add_real_list("structure.box.lower", "box shape: lower corner")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0.35, 0.4, 0.4});
  s.add_real_list("structure.box.upper", "box shape: upper corner")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0.65, 0.6, 0.6});
  s.add_integer_list("structure.box.cells", "box shape: hexahedra per direction")
      .size(3)
      .defaults(std::vector<std::int64_t>{6, 4, 4})
      .at_least(1)
      .at_most(max_mesh_cells);
  s.add_real_list("structure.shell.center", "shell shape: centre")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0.5, 0.5, 0.5});
  s.add_real("structure.shell.inner_radius", "shell shape: inner radius").unit("cm").defaults(0.2).positive();
  s.add_real("structure.shell.outer_radius", "shell shape: outer radius").unit("cm").defaults(0.3).positive();
  s.add_integer("structure.shell.patches", "shell shape: cells along each cube-face patch side")
      .defaults(std::int64_t{8})
      .at_least(1)
      .at_most(max_mesh_cells);
  s.add_integer("structure.shell.layers", "shell shape: cells through the thickness")
      .defaults(std::int64_t{3})
      .at_least(1)
      .at_most(max_mesh_cells);
  s.add_real_list("structure.initial.stretch",
                  "initial stretch of the structure about its centroid (x, y, z)")
      .size(3)
      .defaults(std::vector<double>{1, 1, 1});
  s.add_real(
       "structure.initial.inflated_inner_radius",
       "shell shape: start inflated isochorically (r^3 = R^3 + a) to this inner radius; 0 = not inflated")
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  s.add_integer("structure.quadrature_degree", "Gauss rule degree of the force integrals")
      .defaults(std::int64_t{2})
      .at_least(1)
      .at_most(max_quadrature_degree);
  add_volumetric_integration_key(s, VolumetricIntegration::full);
  s.merge(materials::material_schema("structure.material"));
  s.add_real_list("structure.fiber_direction",
                  "reference fiber direction f0 (normalised) for laws with fibers; [0, 0, 0] = none")
      .size(3)
      .defaults(std::vector<double>{0, 0, 0});
  io::Schema part;
  part.add_string("group", "a volume group of the mesh").required();
  part.add_real_list("fiber_direction", "reference fiber direction f0 of this part; [0, 0, 0] = none")
      .size(3)
      .defaults(std::vector<double>{0, 0, 0});
  part.merge(materials::material_schema("material"));
  s.add_table_list("structure.part", part,
                   "body parts, each a volume group with its own material and fibers (instead of "
                   "[structure.material] for the whole mesh); every element in exactly one part");

  s.add_string("ib.kernel", "regularized delta function")
      .choices({"piecewise-linear", "ib-3", "ib-4", "ib-6", "bspline-3"})
      .defaults(ib::kernel_name(ib::default_kernel));
  s.add_string("ib.velocity_projection", "L2 projection of the interpolated velocity to the nodes")
      .choices({"consistent", "lumped"})
      .defaults(std::string("consistent"));
  s.add_string("ib.force_projection", "L2 projection of the nodal forces to a force density")
      .choices({"consistent", "lumped"})
      .defaults(std::string("consistent"));
  s.add_real("ib.point_spacing", "largest spacing of the coupling points, in grid cells")
      .defaults(0.5)
      .positive();
  io::Schema tether;
  tether.add_string("group", "a physical group of the mesh (surface, volume or points)").required();
  tether
      .add_real("stiffness", "spring stiffness per area (surface), volume (volume) or per node (points), CGS")
      .defaults(0.0)
      .non_negative();
  tether.add_real("damping", "dashpot coefficient, the same per unit velocity, CGS")
      .defaults(0.0)
      .non_negative();
  s.add_table_list("ib.tether", tether, "tethers pulling groups of nodes back to their reference positions");
  io::add_checkpoint_schema(s);
  // Nested grid levels around the structure (walls only): the IB on the finest level (docs/nested.md).
  s.merge(fluid::nested_schema());
}

fe::MassKind mass_kind(const std::string& name)
{
  return name == "lumped" ? fe::MassKind::lumped : fe::MassKind::consistent;
}

class IbfeRun : public PreparedRun {
 public:
  explicit IbfeRun(const io::Config& config) : config_(config)
  {
    box_ = read_fluid_box(config);
    for (int d = 0; d < 3; ++d) box_.periodic[d] = config.string("fluid.boundary") == "periodic";
    fluid_settings_.rho = config.real("fluid.density");
    fluid_settings_.mu = config.real("fluid.viscosity");
    fluid_settings_.solver = box_.periodic[0] ? fluid::SolverKind::fft : fluid::SolverKind::krylov;

    const std::string shape = config.string("structure.shape");
    if (shape == "file") {
      if (!config.has("structure.mesh")) config.fail("structure.shape", "\"file\" needs structure.mesh");
      mesh_ = fe::read_msh(config.path("structure.mesh"));
      check_size(config, static_cast<double>(mesh_.num_nodes()), static_cast<double>(mesh_.num_elements()),
                 "structure.mesh");
    } else if (shape == "box") {
      const auto lo = config.reals("structure.box.lower"), hi = config.reals("structure.box.upper");
      const auto n = config.integers("structure.box.cells");
      for (int d = 0; d < 3; ++d) {
        if (!(hi[d] > lo[d])) config.fail("structure.box.upper", "must lie above structure.box.lower");
        if (n[d] < 1) config.fail("structure.box.cells", "must be at least 1");
      }
      double nodes = 1.0, elements = 1.0;
      for (int d = 0; d < 3; ++d) {
        nodes *= static_cast<double>(n[d]) + 1.0;
        elements *= static_cast<double>(n[d]);
      }
      check_size(config, nodes, elements, "structure.box.cells");
      mesh_ = fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(lo[0], lo[1], lo[2]),
                           fe::Vec3(hi[0], hi[1], hi[2]),
                           {static_cast<int>(n[0]), static_cast<int>(n[1]), static_cast<int>(n[2])});
    } else {
      const auto c = config.reals("structure.shell.center");
      const double ri = config.real("structure.shell.inner_radius"),
                   ro = config.real("structure.shell.outer_radius");
      if (!(ro > ri)) config.fail("structure.shell.outer_radius", "must exceed structure.shell.inner_radius");
      center_ = fe::Vec3(c[0], c[1], c[2]);
      inner_radius_ = ri;
      // Six cube faces of patches x patches cells, `layers` of them through the thickness.
      const double patches = static_cast<double>(config.integer("structure.shell.patches")),
                   layers = static_cast<double>(config.integer("structure.shell.layers"));
      check_size(config, 6.0 * patches * patches * (layers + 1.0), 6.0 * patches * patches * layers,
                 "structure.shell.patches");
      mesh_ = fe::spherical_shell_mesh(center_, ri, ro,
                                       static_cast<int>(config.integer("structure.shell.patches")),
                                       static_cast<int>(config.integer("structure.shell.layers")));
    }
    inflated_ = config.real("structure.initial.inflated_inner_radius");
    if (inflated_ > 0.0 && shape != "spherical-shell")
      config.fail("structure.initial.inflated_inner_radius", "applies to the spherical-shell shape only");
    if (inflated_ > 0.0 && inflated_ < inner_radius_)
      config.fail("structure.initial.inflated_inner_radius",
                  "must not be below structure.shell.inner_radius");
    read_parts(config);

    settings_.kernel = *ib::find_kernel(config.string("ib.kernel"));
    settings_.velocity_projection = mass_kind(config.string("ib.velocity_projection"));
    settings_.force_projection = mass_kind(config.string("ib.force_projection"));
    settings_.points.spacing = config.real("ib.point_spacing");
    if (config.has("ib.tether"))
      for (const io::Config& t : config.tables("ib.tether")) {
        const std::string group = t.string("group");
        if (!mesh_.has_group(group)) t.fail("group", "the mesh has no physical group '" + group + "'");
        settings_.tethers.push_back({group, t.real("stiffness"), t.real("damping")});
      }

    initial_ = initial_displacement(config);
    for (std::size_t n = 0; n < mesh_.num_nodes(); ++n)
      for (int d = 0; d < 3; ++d) {
        const double x = mesh_.nodes()[n][d] + initial_[3 * n + d];
        if (!box_.periodic[d] && !(x > box_.lower[d] && x < box_.upper[d]))
          config.fail(shape == "box"    ? "structure.box.upper"
                      : shape == "file" ? "structure.mesh"
                                        : "structure.shell.center",
                      "the structure must lie inside the walled box");
      }
    if (!config.integers("nested.ratios").empty()) read_levels(config);
    end_ = config.real("time.end");
    dt_ = config.real("time.step");
    every_ = config.integer("output.every");
    checkpoint_settings_ = io::checkpoint_settings_from_config(config);
  }

  RunSummary run(const RunContext& context) override
  {
    auto& log = base::Logger::global();
    fluid::BoundaryConditions bc;
    if (!box_.periodic[0])
      for (int side = 0; side < 6; ++side) bc.side(side).kind = fluid::SideKind::velocity;
    if (context.restart) load_fftw_plans(context); // the interrupted run's FFTW plans: the same bits
    const std::unique_ptr<fluid::FlowSolver> fluid =
        fluid::make_flow_solver(context.comm, box_, hierarchy_.get(), bc, fluid_settings_);
    fluid->set_initial_condition(
        [](const fluid::Real3&, double) {
          return fluid::Real3{0.0, 0.0, 0.0};
        },
        nullptr, 0.0);
    fe::SolidModel solid(mesh_, parts_, static_cast<int>(config_.integer("structure.quadrature_degree")),
                         context.comm);
    solid.set_fibers(fibers_);
    ib::IbfeIntegrator ibfe(*fluid, solid, settings_);
    ibfe.set_displacement(initial_);
    log.info("fluid: " + fluid->describe() + "; the structure on a grid of spacing " +
             std::to_string(ibfe.fluid().grid().h(0)) + " cm");
    log.info("structure: " + std::to_string(mesh_.num_elements()) + " elements, " +
             std::to_string(mesh_.num_nodes()) + " nodes, volume " + std::to_string(mesh_.volume()) +
             " cm^3");
    for (const fe::BodyPart& p : parts_)
      log.info("  part " + p.name + ": " + std::to_string(p.elements.size()) + " elements, " +
               (p.laws.empty() ? p.centre_laws : p.laws).front()->name() +
               (p.centre_laws.empty() ? "" : " + " + p.centre_laws.front()->name() + " penalty (reduced)"));

    const double V0 = mesh_.volume();
    TimeLoop loop;
    loop.comm = context.comm;
    loop.steps = std::max(1L, std::lround(end_ / dt_));
    loop.dt = dt_;
    loop.checkpoints = checkpoint_settings_;
    loop.columns = {"t", "volume", "volume_change", "max_node_speed", "max_displacement", "kinetic_energy"};
    loop.units = {"s", "cm^3", "1", "cm/s", "cm", "erg"};
    loop.fields_every = every_;
    loop.time = [&](std::int64_t) { return ibfe.time(); };
    loop.advance = [&](std::int64_t) { ibfe.step(dt_); };
    loop.row = [&](std::int64_t) {
      double speed = 0.0, displacement = 0.0;
      for (std::size_t n = 0; n < mesh_.num_nodes(); ++n) {
        speed = std::max(speed, Eigen::Vector3d(ibfe.velocity().data() + 3 * n).norm());
        displacement = std::max(displacement, Eigen::Vector3d(ibfe.displacement().data() + 3 * n).norm());
      }
      const double volume = ibfe.volume();
      return std::vector<double>{ibfe.time(), volume,       volume / V0 - 1.0,
                                 speed,       displacement, fluid->kinetic_energy()};
    };
    loop.write_fields = [&](io::XdmfTimeSeries& series, std::int64_t step) {
      write_ibfe_fields(context.comm, context.run_directory, series, mesh_, *fluid, ibfe,
                        static_cast<long>(step));
    };
    // A checkpoint holds the fluid's state and the structure's (docs/runs.md); the fluid comes first.
    loop.save = [&](io::Hdf5File& h5) {
      fluid->save(h5, "fluid");
      ibfe.save(h5, "ibfe");
    };
    loop.restore = [&](const io::Hdf5File& h5) {
      fluid->restore(h5, "fluid");
      ibfe.restore(h5, "ibfe");
    };
    loop.before_save = [&] { save_fftw_plans(context); };
    loop.figures = [&] { return ibfe_step_figures(*fluid, ibfe, dt_); };
    loop.finish = [&](RunSummary& summary, bool, std::size_t snapshots) {
      for (std::string& line :
           ibfe_summary_lines(ibfe, V0, context.run_directory, snapshots, "; " + fluid_summary(*fluid)))
        summary.lines.push_back(std::move(line));
    };
    return run_time_loop(context, loop);
  }

 private:
  // The structure's and the one grid's size, checked before the mesh is built (a box of 2^32 cells a side
  // must not be allocated to find out): indices, then memory. Nested levels add theirs in read_levels.
  void check_size(const io::Config& config, double nodes, double elements, const std::string& key)
  {
    check_index_count(config, key, 3.0 * nodes, "structure unknowns");
    structure_memory_ = structure_memory(nodes, elements, key);
    memory_line_ =
        check_memory(config,
                     {{fluid_memory(grid_cells(box_), memory_kind(fluid_settings_), true, "fluid.cells"),
                       structure_memory_}},
                     PETSC_COMM_WORLD);
  }

  // Nested grid levels (docs/nested.md, "IB on the finest level"): walls only, the finest level one box
  // holding the structure's starting configuration with room for the kernel's reach.
  void read_levels(const io::Config& config)
  {
    if (box_.periodic[0])
      config.fail(
          "nested.ratios",
          "nested grid levels need fluid.boundary = \"walls\" (the composite solver has no periodic box)");
    std::vector<fe::Vec3> positions(mesh_.num_nodes());
    for (std::size_t n = 0; n < positions.size(); ++n)
      for (int d = 0; d < 3; ++d) positions[n][d] = mesh_.nodes()[n][d] + initial_[3 * n + d];
    hierarchy_ = std::make_unique<fluid::GridHierarchy>(
        read_structure_levels(config, box_, positions, settings_.kernel, "structure.shape"));
    const double cells = composite_cells(*hierarchy_);
    memory_line_ =
        check_memory(config,
                     {{fluid_memory(cells, FluidMemoryKind::nested, true,
                                    cells > 2.0 * grid_cells(box_) ? "nested.ratios" : "fluid.cells"),
                       structure_memory_}},
                     PETSC_COMM_WORLD);
    // Centred convection on nested levels: second order on smooth flows (docs/nested.md).
    fluid_settings_.convection = fluid::ConvectionScheme::centered;
  }

  static materials::FiberFrame fiber_frame(const io::Config& config, const std::string& key)
  {
    const auto f = config.reals(key);
    materials::FiberFrame frame;
    const materials::Vec3 f0(f[0], f[1], f[2]);
    if (f0.norm() > 0.0) frame.f0 = f0.normalized();
    return frame;
  }

  // One part per [[structure.part]] (a volume group, its material, its fiber direction), or the whole
  // mesh with [structure.material].
  void read_parts(const io::Config& config)
  {
    fibers_.assign(mesh_.num_elements(), fiber_frame(config, "structure.fiber_direction"));
    const VolumetricIntegration integration = read_volumetric_integration(config);
    if (!config.has("structure.part")) {
      std::vector<int> all(mesh_.num_elements());
      for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
      parts_.push_back(material_part("structure", std::move(all),
                                     materials::read_material(config, "structure.material").build(),
                                     integration));
      return;
    }
    std::vector<int> owner(mesh_.num_elements(), -1);
    for (const io::Config& p : config.tables("structure.part")) {
      const std::string group = p.string("group");
      if (!mesh_.has_group(group) || mesh_.group(group).dimension != 3)
        p.fail("group", "the mesh has no volume group '" + group + "'");
      fe::BodyPart part = material_part(group, mesh_.group(group).elements,
                                        materials::read_material(p, "material").build(), integration);
      const materials::FiberFrame frame = fiber_frame(p, "fiber_direction");
      for (int e : part.elements) {
        if (owner[e] >= 0) p.fail("group", "element " + std::to_string(e) + " is already in another part");
        owner[e] = static_cast<int>(parts_.size());
        fibers_[e] = frame;
      }
      parts_.push_back(std::move(part));
    }
    if (std::find(owner.begin(), owner.end(), -1) != owner.end())
      config.fail("structure.part", "some elements of the mesh are in no part");
  }

  std::vector<double> initial_displacement(const io::Config& config) const
  {
    std::vector<double> u(3 * mesh_.num_nodes(), 0.0);
    fe::Vec3 centroid = fe::Vec3::Zero();
    for (const fe::Vec3& X : mesh_.nodes()) centroid += X;
    centroid /= static_cast<double>(mesh_.num_nodes());
    const auto stretch = config.reals("structure.initial.stretch");
    for (int d = 0; d < 3; ++d)
      if (!(stretch[d] > 0.0)) config.fail("structure.initial.stretch", "stretches must be positive");
    const double a = inflated_ > 0.0 ? std::pow(inflated_, 3) - std::pow(inner_radius_, 3) : 0.0;
    for (std::size_t n = 0; n < mesh_.num_nodes(); ++n) {
      fe::Vec3 x = mesh_.nodes()[n];
      if (a > 0.0) {
        const fe::Vec3 R = x - center_;
        x = center_ + std::cbrt(std::pow(R.norm(), 3) + a) / R.norm() * R;
      }
      for (int d = 0; d < 3; ++d) x[d] = centroid[d] + stretch[d] * (x[d] - centroid[d]);
      for (int d = 0; d < 3; ++d) u[3 * n + d] = x[d] - mesh_.nodes()[n][d];
    }
    return u;
  }

  io::Config config_;
  fluid::BoxGeometry box_;
  fluid::FluidSettings fluid_settings_;
  fe::Mesh mesh_;
  std::vector<fe::BodyPart> parts_;
  std::vector<materials::FiberFrame> fibers_;
  ib::IbfeSettings settings_;
  std::vector<double> initial_;
  fe::Vec3 center_ = fe::Vec3::Zero();
  double inner_radius_ = 0.0, inflated_ = 0.0, end_ = 0.0, dt_ = 0.0;
  long every_ = 1;
  io::CheckpointSettings checkpoint_settings_;
  std::unique_ptr<fluid::GridHierarchy> hierarchy_; // nested levels; null on one grid
  MemoryPart structure_memory_;
};

} // namespace

Model ibfe_model()
{
  return {"ibfe",
          "an elastic structure (FE mesh) immersed in fluid on a staggered grid, coupled by the IB/FE method",
          add_ibfe_schema, [](const io::Config& config) { return std::make_unique<IbfeRun>(config); }};
}

} // namespace ibvalve::app
