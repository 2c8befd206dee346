#include "fibers/rules.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::fibers {

FiberRule parse_fiber_rule(const std::string& text)
{
  std::string upper = text;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  if (upper == "FD1") return FiberRule::FD1;
  if (upper == "FD2") return FiberRule::FD2;
  throw InputError("fibers: rule '" + text + "' is not known (FD1 or FD2)");
}

namespace {

// The explicit selector, else "<leaflet>_<role>", else "<role>"; empty when none exists.
std::string default_selector(const fe::Mesh& mesh, const LeafletSpec& spec, const std::string& given,
                             const std::string& role)
{
  if (!given.empty()) return given;
  if (!spec.group.empty() && mesh.has_group(spec.group + "_" + role)) return spec.group + "_" + role;
  if (mesh.has_group(role)) return role;
  return "";
}

std::vector<DirichletSet> leaflet_conditions(const fe::Mesh& part, FiberRule rule, const LeafletSpec& spec,
                                             const std::string& label)
{
  auto require = [&](const std::string& selector, const std::string& role) {
    if (selector.empty())
      throw InputError("fibers: leaflet " + label + ": no " + role +
                       " (give a selector or a physical group named " +
                       (spec.group.empty() ? "" : spec.group + "_" + role + " or ") + role + ")");
    return select_nodes(part, selector);
  };
  if (rule == FiberRule::FD1) {
    return {DirichletSet{require(default_selector(part, spec, spec.n1, "n1"), "n1"), 1.0},
            DirichletSet{require(default_selector(part, spec, spec.n2, "n2"), "n2"), 0.0}};
  }
  const std::string tau1 = default_selector(part, spec, spec.tau1, "tau1");
  const std::string tau2 = default_selector(part, spec, spec.tau2, "tau2");
  if (!tau1.empty() || !tau2.empty())
    return {DirichletSet{require(tau1, "tau1"), 0.0}, DirichletSet{require(tau2, "tau2"), 1.0}};
  // Split the attachment surface by the plane through the axis and the leaflet's centroid.
  const std::string attachment = default_selector(part, spec, spec.attachment, "attachment");
  const std::vector<int> nodes = require(attachment, "tau1/tau2 or attachment");
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& x : part.nodes()) centroid += x / static_cast<double>(part.num_nodes());
  const Vec3 d = spec.axis_direction.normalized();
  Vec3 radial = centroid - spec.axis_point;
  radial -= radial.dot(d) * d;
  if (radial.norm() < 1e-12 * part.edge_length_range().second)
    throw InputError("fibers: leaflet " + label + ": its centroid lies on the axis; give tau1 and tau2");
  const Vec3 normal = d.cross(radial).normalized();
  const double tolerance = 1e-6 * part.edge_length_range().first;
  DirichletSet first{{}, 0.0}, second{{}, 1.0};
  for (int n : nodes) {
    const double side = (part.nodes()[n] - spec.axis_point).dot(normal);
    if (side < -tolerance) first.nodes.push_back(n);
    if (side > tolerance) second.nodes.push_back(n);
  }
  if (first.nodes.empty() || second.nodes.empty())
    throw InputError("fibers: leaflet " + label + ": the attachment '" + attachment +
                     "' does not lie on both sides of the leaflet's centre plane");
  return {first, second};
}

} // namespace

FiberField compute_fibers(const fe::Mesh& mesh, FiberRule rule, const std::vector<LeafletSpec>& leaflets,
                          MPI_Comm comm, const LaplaceOptions& options)
{
  FiberField field;
  field.element_directions.assign(mesh.num_elements(), Vec3::Zero());
  field.potential.assign(mesh.num_nodes(), 0.0);
  field.dirichlet.assign(mesh.num_nodes(), -1.0);
  std::vector<LeafletSpec> specs = leaflets;
  if (specs.empty()) specs.push_back(LeafletSpec{});
  for (const LeafletSpec& spec : specs) {
    std::vector<int> elements;
    if (spec.group.empty()) {
      elements.resize(mesh.num_elements());
      for (std::size_t e = 0; e < elements.size(); ++e) elements[e] = static_cast<int>(e);
    } else {
      const fe::PhysicalGroup& group = mesh.group(spec.group);
      if (group.dimension != 3)
        throw InputError("fibers: leaflet group '" + spec.group + "' is not a volume group");
      elements = group.elements;
    }
    std::vector<int> node_map;
    const fe::Mesh part = fe::submesh(mesh, elements, &node_map);
    const std::string label = spec.group.empty() ? "(whole mesh)" : "'" + spec.group + "'";
    const std::vector<DirichletSet> conditions = leaflet_conditions(part, rule, spec, label);
    const std::vector<double> u = solve_laplace(part, conditions, comm, options);
    const fe::QuadratureData quadrature(part, 2);
    const std::vector<Vec3> directions = directions_per_element(part, quadrature, u);
    for (std::size_t e = 0; e < elements.size(); ++e) field.element_directions[elements[e]] = directions[e];
    for (std::size_t n = 0; n < node_map.size(); ++n) field.potential[node_map[n]] = u[n];
    for (const auto& set : conditions)
      for (int n : set.nodes) field.dirichlet[node_map[n]] = set.value;
  }
  return field;
}

void write_element_fibers(const std::filesystem::path& path, const std::vector<Vec3>& directions,
                          MPI_Comm comm)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank != 0) return;
  std::ostringstream out;
  out << "ibvalve-element-fibers 1 " << directions.size() << "\n" << std::setprecision(17);
  for (const Vec3& f : directions) out << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  io::write_file_atomically(path, out.str());
}

std::vector<Vec3> read_element_fibers(const std::filesystem::path& path, long expected_elements)
{
  const std::string text = io::read_text_file(path);
  std::istringstream in(text);
  std::string line;
  const std::string where = path.string() + ":";
  std::getline(in, line);
  std::istringstream header(line);
  std::string magic;
  int version = 0;
  long count = -1;
  if (!(header >> magic >> version >> count) || magic != "ibvalve-element-fibers" || version != 1 ||
      count < 0)
    throw InputError(where + "1: not an ibvalve element fiber file (header 'ibvalve-element-fibers 1 N')");
  if (expected_elements >= 0 && count != expected_elements)
    throw InputError(fmt::format("{}1: the file has fibers for {} elements, the mesh has {}", where, count,
                                 expected_elements));
  std::vector<Vec3> directions;
  directions.reserve(count);
  for (long e = 0; e < count; ++e) {
    Vec3 f;
    if (!std::getline(in, line)) throw InputError(fmt::format("{}{}: the file ends early", where, e + 2));
    std::istringstream row(line);
    if (!(row >> f[0] >> f[1] >> f[2]) || !f.allFinite())
      throw InputError(fmt::format("{}{}: expected three numbers", where, e + 2));
    directions.push_back(f);
  }
  return directions;
}

} // namespace ibvalve::fibers
