#include "io/xdmf.hpp"

#include <fmt/format.h>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "io/collective.hpp"
#include "io/files.hpp"

namespace ibvalve::io {

namespace {

// The indentation of the temporal collection's grids, one per step (resume finds them by it).
const std::string step_indent(6, ' ');

} // namespace

XdmfGrid XdmfGrid::regular(std::string name, std::array<std::size_t, 3> cells, std::array<double, 3> origin,
                           std::array<double, 3> spacing)
{
  XdmfGrid g;
  g.name = std::move(name);
  g.cells = cells;
  g.origin = origin;
  g.spacing = spacing;
  return g;
}

XdmfGrid XdmfGrid::mesh(std::string name, std::string topology, std::size_t elements,
                        std::size_t nodes_per_element, std::string connectivity, std::size_t nodes,
                        std::string coordinates)
{
  XdmfGrid g;
  g.name = std::move(name);
  g.topology = std::move(topology);
  g.elements = elements;
  g.nodes_per_element = nodes_per_element;
  g.connectivity = std::move(connectivity);
  g.nodes = nodes;
  g.coordinates = std::move(coordinates);
  return g;
}

XdmfGrid& XdmfGrid::add_field(std::string field_name, Center center, std::vector<std::size_t> dims,
                              std::string data, std::string units, bool integer)
{
  fields.push_back(
      {std::move(field_name), center, std::move(dims), std::move(data), std::move(units), integer});
  return *this;
}

XdmfGrid& XdmfGrid::add_information(std::string info_name, std::string value)
{
  information.push_back({std::move(info_name), std::move(value)});
  return *this;
}

XdmfTimeSeries::XdmfTimeSeries(MPI_Comm comm, std::filesystem::path path, std::string name)
    : comm_(comm), path_(std::move(path)), name_(std::move(name))
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  writer_ = rank == 0;
}

void XdmfTimeSeries::add_step(double time, std::vector<XdmfGrid> grids)
{
  steps_.emplace_back(time, step_text(time, grids));
  write();
}

void XdmfTimeSeries::drop_after(double time)
{
  while (!steps_.empty() && steps_.back().first > time) steps_.pop_back();
  write();
}

void XdmfTimeSeries::resume(double time)
{
  // The file holds one grid per step between the temporal collection's opening and closing lines
  // (text() below), each opening and closing at the steps' indentation (the grids inside a step's
  // collection are indented further); each names its time with 17 digits, so the times read back exactly.
  steps_.clear();
  long kept = 0;
  if (writer_ && std::filesystem::exists(path_)) {
    const std::string text = read_text_file(path_);
    const std::string opening = "\n" + step_indent + "<Grid ", closing = "\n" + step_indent + "</Grid>\n",
                      value = "<Time Value=\"";
    for (std::size_t begin = text.find(opening); begin != std::string::npos;
         begin = text.find(opening, begin)) {
      ++begin; // the step's text starts after the line break
      const std::size_t end = text.find(closing, begin);
      const std::size_t at = text.find(value, begin);
      if (end == std::string::npos || at == std::string::npos || at > end)
        throw std::runtime_error(path_.string() + ": not an XDMF time series of ibvalve");
      const double t = std::stod(text.substr(at + value.size()));
      if (t > time) break;
      steps_.emplace_back(t, text.substr(begin, end + closing.size() - begin));
      begin = end + closing.size() - 1;
    }
    kept = static_cast<long>(steps_.size());
  }
  // The other ranks only count the steps (steps() is the same everywhere).
  MPI_Bcast(&kept, 1, MPI_LONG, 0, comm_);
  if (!writer_) steps_.assign(static_cast<std::size_t>(kept), {0.0, std::string()});
  write();
}

void XdmfTimeSeries::write() const
{
  // Rank 0 writes; a failure there (a full disk) reaches every rank.
  on_root(comm_, [&] { write_file_atomically(path_, text()); });
}

namespace {

std::string dims_text(const std::vector<std::size_t>& dims)
{
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i) s += fmt::format("{}{}", (i ? " " : ""), dims[i]);
  return s;
}

void data_item(std::ostringstream& os, const std::vector<std::size_t>& dims, const std::string& number_type,
               const std::string& data, const std::string& indent)
{
  os << indent << "<DataItem Dimensions=\"" << dims_text(dims) << "\" NumberType=\"" << number_type
     << "\" Precision=\"8\" Format=\"HDF\">" << xml_escaped(data) << "</DataItem>\n";
}

/// One grid at `indent`, its elements indented further; `time`, when given, as its Time element.
void grid_text(std::ostringstream& os, const XdmfGrid& g, const std::string& indent, const double* time)
{
  const std::string in = indent + "  ";
  os << indent << "<Grid Name=\"" << xml_escaped(g.name) << "\" GridType=\"Uniform\">\n";
  if (time) os << in << "<Time Value=\"" << *time << "\"/>\n";
  for (const XdmfInformation& info : g.information)
    os << in << "<Information Name=\"" << xml_escaped(info.name) << "\" Value=\"" << xml_escaped(info.value)
       << "\"/>\n";
  std::size_t grid_rank = 0;
  if (g.topology.empty()) {
    // XDMF orders regular-grid dimensions slowest first: z, y, x (points, not cells).
    os << in << "<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" << g.cells[2] + 1 << " "
       << g.cells[1] + 1 << " " << g.cells[0] + 1 << "\"/>\n";
    os << in << "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
    os << in << "  <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">"
       << g.origin[2] << " " << g.origin[1] << " " << g.origin[0] << "</DataItem>\n";
    os << in << "  <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">"
       << g.spacing[2] << " " << g.spacing[1] << " " << g.spacing[0] << "</DataItem>\n";
    os << in << "</Geometry>\n";
    grid_rank = 3;
  } else {
    os << in << "<Topology TopologyType=\"" << g.topology << "\" NumberOfElements=\"" << g.elements << "\"";
    if (g.topology == "Polyvertex") os << " NodesPerElement=\"1\"";
    os << ">\n";
    data_item(os, {g.elements, g.nodes_per_element}, "Int", g.connectivity, in + "  ");
    os << in << "</Topology>\n";
    os << in << "<Geometry GeometryType=\"XYZ\">\n";
    data_item(os, {g.nodes, 3}, "Float", g.coordinates, in + "  ");
    os << in << "</Geometry>\n";
    grid_rank = 1;
  }
  for (const XdmfField& f : g.fields) {
    std::string type = "Scalar";
    if (f.dims.size() > grid_rank)
      type = f.dims.back() == 3 ? "Vector" : f.dims.back() == 9 ? "Tensor" : "Matrix";
    os << in << "<Attribute Name=\"" << xml_escaped(f.shown_name()) << "\" AttributeType=\"" << type
       << "\" Center=\"" << (f.center == Center::cell ? "Cell" : "Node") << "\">\n";
    data_item(os, f.dims, f.integer ? "Int" : "Float", f.data, in + "  ");
    os << in << "</Attribute>\n";
  }
  os << indent << "</Grid>\n";
}

} // namespace

std::string XdmfTimeSeries::step_text(double time, const std::vector<XdmfGrid>& grids) const
{
  // The time's grid is named as the series' grids are, not after the time: ParaView names a block by
  // it, and a block renamed from one time to the next is another block.
  std::ostringstream os;
  os << std::setprecision(17);
  if (grids.size() == 1) {
    grid_text(os, grids.front(), step_indent, &time);
    return os.str();
  }
  os << step_indent << "<Grid Name=\"" << xml_escaped(name_)
     << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
  os << step_indent << "  <Time Value=\"" << time << "\"/>\n";
  for (const XdmfGrid& g : grids) grid_text(os, g, step_indent + "  ", nullptr);
  os << step_indent << "</Grid>\n";
  return os.str();
}

std::string XdmfTimeSeries::text() const
{
  std::ostringstream os;
  os << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n  "
        "<Domain>\n";
  os << "    <Grid Name=\"" << xml_escaped(name_)
     << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& step : steps_) os << step.second;
  os << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return os.str();
}

} // namespace ibvalve::io
