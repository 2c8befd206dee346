// `model = "ibfe"`: an elastic structure (a finite-element mesh) immersed in viscous incompressible
// fluid on a staggered grid, coupled by the IB/FE method (ib/ibfe.hpp; docs/ib.md). The structure is
// read from a Gmsh file or generated (a box of hexahedra, a thick spherical shell), may start from a
// stretched or inflated configuration, and may be tethered. Output: fields/*.h5 with fields_fluid.xdmf
// (the grid's velocity, vorticity and pressure) and fields_structure.xdmf (the mesh's displacement,
// velocity, J, fiber strain and the Cauchy stress along the fiber), two datasets one ParaView state
// opens side by side, and timeseries.csv.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <memory>
#include <optional>

#include <mpi.h>

#include "app/fftw_plans.hpp"
#include "app/fluid_box.hpp"
#include "app/ibfe_fields.hpp"
#include "app/model.hpp"
#include "app/output_keys.hpp"
#include "app/resource_estimate.hpp"
#include "app/step_schedule.hpp"
#include "app/structure_levels.hpp"
#include "app/structure_parts.hpp"
#include "app/time_loop.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/mesh.hpp"
#include "fe/shell_mesh.hpp"
#include "fe/solid.hpp"
#include "fe/volumetric_integration.hpp"
#include "fluid/flow_solver.hpp"
#include "fluid/hierarchy.hpp"
#include "ib/eulerian_fluid.hpp"
#include "ib/ibfe.hpp"
#include "ib/keys.hpp"
#include "io/checkpoint.hpp"
#include "io/files.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

namespace {

enum class Shape { file, box, spherical_shell };

/// One [[structure.part]]: a volume group, its material, its fiber direction.
struct PartKeys {
  std::string group;
  std::vector<double> fiber_direction;
  materials::MaterialKeys material;
};

void bind(io::KeyBinder& keys, PartKeys& p)
{
  keys.string("group", "a volume group of the mesh", p.group).required();
  keys.reals("fiber_direction", "reference fiber direction f0 of this part; [0, 0, 0] = none",
             p.fiber_direction)
      .size(3)
      .defaults(std::vector<double>{0, 0, 0});
  materials::bind(keys, p.material, "material");
}

/// The model's own keys and where they go (io/key_binder.hpp); the materials, the volumetric integration,
/// the coupling (ib.*), checkpoints and nested levels are their folders' sections.
struct IbfeKeys {
  double end = 0, step = 0;
  std::optional<double> fields_interval;
  fluid::FluidSettings fluid;
  std::vector<std::int64_t> cells;
  std::vector<double> lower, upper;
  bool periodic = true;
  Shape shape = Shape::box;
  std::filesystem::path mesh;
  std::vector<double> box_lower, box_upper;
  std::vector<std::int64_t> box_cells;
  std::vector<double> shell_center;
  double inner_radius = 0, outer_radius = 0;
  std::int64_t patches = 8, layers = 3;
  std::vector<double> stretch;
  double inflated_inner_radius = 0;
  int quadrature_degree = 2;
  fe::VolumetricIntegration volumetric_integration = fe::VolumetricIntegration::full;
  materials::MaterialKeys material; // the whole mesh's, without [[structure.part]]
  std::vector<double> fiber_direction;
  std::vector<PartKeys> parts;
  ib::IbfeSettings ib; // with its tethers
  io::CheckpointSettings checkpoints;
  fluid::NestedKeys nested;
};

/// The run's length and outputs, and the fluid's box: time.*, output.*, fluid.*.
void bind_time_and_fluid(io::KeyBinder& keys, IbfeKeys& k)
{
  keys.real("time.end", "simulated time", k.end).unit("s").defaults(0.05).positive();
  keys.real("time.step", "time step of the coupled scheme (see the stability estimate in the log)", k.step)
      .unit("s")
      .defaults(1e-3)
      .positive();
  bind_fields_interval(keys, k.fields_interval, 0.01, "fields_fluid.xdmf and fields_structure.xdmf");
  retire_every_as_fields(keys);
  bind_fluid_density(keys, k.fluid.rho, "fluid density");
  bind_fluid_viscosity(keys, k.fluid.mu, 4.0);
  keys.integers("fluid.cells", "grid cells in x, y, z", k.cells)
      .size(3)
      .at_most(max_grid_cells)
      .defaults(std::vector<std::int64_t>{32, 32, 32});
  keys.reals("fluid.lower", "lower corner of the box", k.lower)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0, 0, 0});
  keys.reals("fluid.upper", "upper corner of the box", k.upper)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{1, 1, 1});
  keys.choice("fluid.boundary", "periodic box (FFT solver) or no-slip walls on every side (Krylov solver)",
              k.periodic, {{"periodic", true}, {"walls", false}})
      .defaults(std::string("periodic"));
}

/// The structure: where its mesh comes from, its starting configuration, its materials: structure.*.
void bind_structure(io::KeyBinder& keys, IbfeKeys& k)
{
  keys.choice("structure.shape", "where the mesh comes from: a Gmsh file, a generated box or spherical shell",
              k.shape,
              {{"file", Shape::file}, {"box", Shape::box}, {"spherical-shell", Shape::spherical_shell}})
      .defaults(std::string("box"));
  keys.path("structure.mesh", "Gmsh mesh (.msh) of hexahedra or tetrahedra, when shape = \"file\"", k.mesh);
  keys.reals("structure.box.lower", "box shape: lower corner", k.box_lower)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0.35, 0.4, 0.4});
  keys.reals("structure.box.upper", "box shape: upper corner", k.box_upper)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0.65, 0.6, 0.6});
  keys.integers("structure.box.cells", "box shape: hexahedra per direction", k.box_cells)
      .size(3)
      .defaults(std::vector<std::int64_t>{6, 4, 4})
      .at_least(1)
      .at_most(max_mesh_cells);
  keys.reals("structure.shell.center", "shell shape: centre", k.shell_center)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{0.5, 0.5, 0.5});
  keys.real("structure.shell.inner_radius", "shell shape: inner radius", k.inner_radius)
      .unit("cm")
      .defaults(0.2)
      .positive();
  keys.real("structure.shell.outer_radius", "shell shape: outer radius", k.outer_radius)
      .unit("cm")
      .defaults(0.3)
      .positive();
  keys.integer("structure.shell.patches", "shell shape: cells along each cube-face patch side", k.patches)
      .defaults(std::int64_t{8})
      .at_least(1)
      .at_most(max_mesh_cells);
  keys.integer("structure.shell.layers", "shell shape: cells through the thickness", k.layers)
      .defaults(std::int64_t{3})
      .at_least(1)
      .at_most(max_mesh_cells);
  keys.reals("structure.initial.stretch", "initial stretch of the structure about its centroid (x, y, z)",
             k.stretch)
      .size(3)
      .defaults(std::vector<double>{1, 1, 1});
  keys.real(
          "structure.initial.inflated_inner_radius",
          "shell shape: start inflated isochorically (r^3 = R^3 + a) to this inner radius; 0 = not inflated",
          k.inflated_inner_radius)
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  keys.integer("structure.quadrature_degree", "Gauss rule degree of the force integrals", k.quadrature_degree)
      .defaults(std::int64_t{2})
      .at_least(1)
      .at_most(max_quadrature_degree);
  fe::bind(keys, k.volumetric_integration, fe::VolumetricIntegration::full);
  materials::bind(keys, k.material, "structure.material");
  keys.reals("structure.fiber_direction",
             "reference fiber direction f0 (normalised) for laws with fibers; [0, 0, 0] = none",
             k.fiber_direction)
      .size(3)
      .defaults(std::vector<double>{0, 0, 0});
  keys.tables("structure.part",
              "body parts, each a volume group with its own material and fibers (instead of "
              "[structure.material] for the whole mesh); every element in exactly one part",
              k.parts, [](io::KeyBinder& part, PartKeys& p) { bind(part, p); });
}

void bind(io::KeyBinder& keys, IbfeKeys& k)
{
  bind_time_and_fluid(keys, k);
  bind_structure(keys, k);
  ib::bind(keys, k.ib, 0.5);
  ib::bind_projections(keys, k.ib);
  ib::bind_tethers(keys, k.ib.tethers);
  io::bind(keys, k.checkpoints);
  // Nested grid levels around the structure (walls only): the IB on the finest level (docs/nested.md).
  fluid::bind(keys, k.nested);
}

class IbfeRun : public PreparedRun {
 public:
  explicit IbfeRun(const io::Config& config) : config_(config), keys_(config_)
  {
    bind(keys_, k_);
    const IbfeKeys& k = k_;
    box_ = fluid_box(keys_, k.cells, k.lower, k.upper);
    for (int d = 0; d < 3; ++d) box_.periodic[d] = k.periodic;
    fluid_settings_ = k.fluid;
    fluid_settings_.solver = box_.periodic[0] ? fluid::SolverKind::fft : fluid::SolverKind::krylov;
    if (const std::string why = step_count_problem(k.end, k.step); !why.empty()) keys_.fail(k.step, why);

    if (k.shape == Shape::file) {
      if (k.mesh.empty()) keys_.fail(k.shape, "\"file\" needs " + keys_.key_of(k.mesh));
      mesh_ = fe::read_msh(k.mesh);
      check_size(static_cast<double>(mesh_.num_nodes()), static_cast<double>(mesh_.num_elements()),
                 keys_.key_of(k.mesh));
    } else if (k.shape == Shape::box) {
      const auto &lo = k.box_lower, &hi = k.box_upper;
      const auto& n = k.box_cells;
      for (int d = 0; d < 3; ++d) {
        if (!(hi[d] > lo[d])) keys_.fail(k.box_upper, "must lie above " + keys_.key_of(k.box_lower));
        if (n[d] < 1) keys_.fail(k.box_cells, "must be at least 1");
      }
      double nodes = 1.0, elements = 1.0;
      for (int d = 0; d < 3; ++d) {
        nodes *= static_cast<double>(n[d]) + 1.0;
        elements *= static_cast<double>(n[d]);
      }
      check_size(nodes, elements, keys_.key_of(k.box_cells));
      mesh_ = fe::box_mesh(fe::CellShape::hexahedron, fe::Vec3(lo[0], lo[1], lo[2]),
                           fe::Vec3(hi[0], hi[1], hi[2]),
                           {static_cast<int>(n[0]), static_cast<int>(n[1]), static_cast<int>(n[2])});
    } else {
      const auto& c = k.shell_center;
      const double ri = k.inner_radius, ro = k.outer_radius;
      if (!(ro > ri)) keys_.fail(k.outer_radius, "must exceed " + keys_.key_of(k.inner_radius));
      center_ = fe::Vec3(c[0], c[1], c[2]);
      inner_radius_ = ri;
      // Six cube faces of patches x patches cells, `layers` of them through the thickness.
      const double patches = static_cast<double>(k.patches), layers = static_cast<double>(k.layers);
      check_size(6.0 * patches * patches * (layers + 1.0), 6.0 * patches * patches * layers,
                 keys_.key_of(k.patches));
      mesh_ =
          fe::spherical_shell_mesh(center_, ri, ro, static_cast<int>(k.patches), static_cast<int>(k.layers));
    }
    inflated_ = k.inflated_inner_radius;
    if (inflated_ > 0.0 && k.shape != Shape::spherical_shell)
      keys_.fail(k.inflated_inner_radius, "applies to the spherical-shell shape only");
    if (inflated_ > 0.0 && inflated_ < inner_radius_)
      keys_.fail(k.inflated_inner_radius, "must not be below " + keys_.key_of(k.inner_radius));
    read_parts();

    for (const ib::Tether& t : k.ib.tethers)
      if (!mesh_.has_group(t.group)) keys_.fail(t.group, "the mesh has no physical group '" + t.group + "'");
    settings_ = k.ib;

    initial_ = initial_displacement();
    for (std::size_t n = 0; n < mesh_.num_nodes(); ++n)
      for (int d = 0; d < 3; ++d) {
        const double x = mesh_.nodes()[n][d] + initial_[3 * n + d];
        if (!box_.periodic[d] && !(x > box_.lower[d] && x < box_.upper[d]))
          config.fail(k.shape == Shape::box    ? keys_.key_of(k.box_upper)
                      : k.shape == Shape::file ? keys_.key_of(k.mesh)
                                               : keys_.key_of(k.shell_center),
                      "the structure must lie inside the walled box");
      }
    if (!k.nested.ratios.empty()) read_levels(config);
    k_.checkpoints.case_record = io::case_record(config);
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
    fe::SolidModel solid(mesh_, parts_, k_.quadrature_degree, context.comm);
    solid.set_fibers(fibers_);
    ib::IbfeIntegrator ibfe(*fluid, solid, settings_);
    ibfe.set_displacement(initial_);
    log.info(fmt::format("fluid: {}; the structure on a grid of spacing {:g} cm", fluid->describe(),
                         ibfe.fluid().grid().h(0)));
    log.info(fmt::format("structure: {} elements, {} nodes, volume {:g} cm^3", mesh_.num_elements(),
                         mesh_.num_nodes(), mesh_.volume()));
    for (const fe::BodyPart& p : parts_)
      log.info(fmt::format(
          "  part {}: {} elements, {}{}", p.name, p.elements.size(),
          (p.laws.empty() ? p.centre_laws : p.laws).front()->name(),
          (p.centre_laws.empty() ? "" : " + " + p.centre_laws.front()->name() + " penalty (reduced)")));

    const double V0 = mesh_.volume();
    TimeLoop loop;
    loop.comm = context.comm;
    loop.steps = std::max(1L, std::lround(k_.end / k_.step));
    loop.end_time = static_cast<double>(loop.steps) * k_.step;
    loop.checkpoints = k_.checkpoints;
    loop.columns = {"t", "volume", "volume_change", "max_node_speed", "max_displacement", "kinetic_energy"};
    loop.units = {"s", "cm^3", "1", "cm/s", "cm", "erg"};
    loop.fields_every = fields_every_steps(k_.fields_interval, k_.step);
    set_ibfe_hooks(loop, context, mesh_, *fluid, ibfe, k_.step);
    loop.advance = [&](std::int64_t) { ibfe.step(k_.step); };
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
  void check_size(double nodes, double elements, const std::string& key)
  {
    check_index_count(config_, key, 3.0 * nodes, "structure unknowns");
    structure_memory_ = structure_memory(nodes, elements, key);
    memory_line_ = check_memory(
        config_,
        {{fluid_memory(grid_cells(box_), memory_kind(fluid_settings_), true, keys_.key_of(k_.cells)),
          structure_memory_}},
        PETSC_COMM_WORLD);
  }

  // Nested grid levels (docs/nested.md, "IB on the finest level"): walls only, the finest level one box
  // holding the structure's starting configuration with room for the kernel's reach.
  void read_levels(const io::Config& config)
  {
    if (box_.periodic[0])
      keys_.fail(k_.nested.ratios, "nested grid levels need " + keys_.key_of(k_.periodic) +
                                       " = \"walls\" (the composite solver has no periodic box)");
    if (k_.ib.coupling == ib::CouplingKind::semi_implicit)
      keys_.fail(k_.ib.coupling, "\"semi-implicit\" needs the fluid on one grid, not on the levels of " +
                                     keys_.key_of(k_.nested.ratios));
    std::vector<fe::Vec3> positions(mesh_.num_nodes());
    for (std::size_t n = 0; n < positions.size(); ++n)
      for (int d = 0; d < 3; ++d) positions[n][d] = mesh_.nodes()[n][d] + initial_[3 * n + d];
    hierarchy_ = std::make_unique<fluid::GridHierarchy>(
        read_structure_levels(keys_, k_.nested, box_, positions, settings_.kernel, keys_.key_of(k_.shape)));
    memory_line_ = check_memory(
        config,
        {{nested_fluid_memory(*hierarchy_, box_, keys_.key_of(k_.cells), keys_.key_of(k_.nested.ratios)),
          structure_memory_}},
        PETSC_COMM_WORLD);
    // Centred convection on nested levels: second order on smooth flows (docs/nested.md).
    fluid_settings_.convection = fluid::ConvectionScheme::centered;
  }

  static materials::FiberFrame fiber_frame(const std::vector<double>& f)
  {
    materials::FiberFrame frame;
    const materials::Vec3 f0(f[0], f[1], f[2]);
    if (f0.norm() > 0.0) frame.f0 = f0.normalized();
    return frame;
  }

  // One part per [[structure.part]] (a volume group, its material, its fiber direction), or the whole
  // mesh with [structure.material].
  void read_parts()
  {
    fibers_.assign(mesh_.num_elements(), fiber_frame(k_.fiber_direction));
    const fe::VolumetricIntegration integration = k_.volumetric_integration;
    if (k_.parts.empty()) {
      std::vector<int> all(mesh_.num_elements());
      for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
      const int families = fiber_frame(k_.fiber_direction).f0.norm() > 0.0 ? 1 : 0;
      parts_.push_back(fe::material_part("structure", std::move(all),
                                         part_material(keys_, k_.material, families).build(), integration));
      return;
    }
    std::vector<int> owner(mesh_.num_elements(), -1);
    for (const PartKeys& p : k_.parts) {
      if (!mesh_.has_group(p.group) || mesh_.group(p.group).dimension != 3)
        keys_.fail(p.group, "the mesh has no volume group '" + p.group + "'");
      const materials::FiberFrame frame = fiber_frame(p.fiber_direction);
      fe::BodyPart part = fe::material_part(
          p.group, mesh_.group(p.group).elements,
          part_material(keys_, p.material, frame.f0.norm() > 0.0 ? 1 : 0).build(), integration);
      for (int e : part.elements) {
        if (owner[e] >= 0) keys_.fail(p.group, fmt::format("element {} is already in another part", e));
        owner[e] = static_cast<int>(parts_.size());
        fibers_[e] = frame;
      }
      parts_.push_back(std::move(part));
    }
    if (std::find(owner.begin(), owner.end(), -1) != owner.end())
      keys_.fail(k_.parts, "some elements of the mesh are in no part");
  }

  std::vector<double> initial_displacement() const
  {
    std::vector<double> u(3 * mesh_.num_nodes(), 0.0);
    fe::Vec3 centroid = fe::Vec3::Zero();
    for (const fe::Vec3& X : mesh_.nodes()) centroid += X;
    centroid /= static_cast<double>(mesh_.num_nodes());
    const auto& stretch = k_.stretch;
    for (int d = 0; d < 3; ++d)
      if (!(stretch[d] > 0.0)) keys_.fail(k_.stretch, "stretches must be positive");
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
  io::KeyBinder keys_; // reads config_ into k_, and names a key in a message
  IbfeKeys k_;
  fluid::BoxGeometry box_;
  fluid::FluidSettings fluid_settings_;
  fe::Mesh mesh_;
  std::vector<fe::BodyPart> parts_;
  std::vector<materials::FiberFrame> fibers_;
  ib::IbfeSettings settings_;
  std::vector<double> initial_;
  fe::Vec3 center_ = fe::Vec3::Zero();
  double inner_radius_ = 0.0, inflated_ = 0.0;
  std::unique_ptr<fluid::GridHierarchy> hierarchy_; // nested levels; null on one grid
  MemoryPart structure_memory_;
};

} // namespace

Model ibfe_model()
{
  return {"ibfe",
          "an elastic structure (FE mesh) immersed in fluid on a staggered grid, coupled by the IB/FE method",
          add_bound_schema<IbfeKeys>,
          [](const io::Config& config) { return std::make_unique<IbfeRun>(config); }};
}

} // namespace ibvalve::app
