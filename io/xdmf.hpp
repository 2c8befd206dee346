#pragma once
// XDMF (version 3) descriptions of HDF5 data, so ParaView and VisIt open a run's fields.
//
// A series is a temporal collection with one grid per output time: the one grid a step holds (a run's
// fluid on one level, its structure), or a spatial collection of a step's grids (the level boxes of
// nested levels) named after the series. The name of a time's grid is the same at every time, so
// ParaView keeps one block of one name as the animation runs; a run writes its fluid and its structure
// as two series (fields_fluid.xdmf, fields_structure.xdmf), which ParaView opens as two datasets.
// The file is rewritten atomically after every output, so it is always complete.
//
// Outputs explain themselves: a field with units is shown as "name [units]" (the name ParaView lists;
// spaces and brackets are plain XML attribute text), and a grid may carry Information elements
// (name/value text, e.g. the structure's part ids and what its coordinates are).
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <mpi.h>

namespace ibvalve::io {

enum class Center { node, cell };

struct XdmfField {
  std::string name;
  Center center = Center::cell;
  /// Shape of the dataset: the grid's (slowest index first) and, for vectors/tensors, 3 or 9 last.
  std::vector<std::size_t> dims;
  /// "path/relative/to/the/xdmf.h5:/dataset"
  std::string data;
  /// CGS units ("cm/s", "dyn/cm^2", "1" for a pure number); empty for labels such as part ids.
  std::string units;
  /// int64 data (part ids) rather than doubles.
  bool integer = false;
  /// The name with its units, as ParaView lists it: "velocity [cm/s]"; a pure number ("1") or a label
  /// keeps its bare name ("J", "part").
  std::string shown_name() const { return units.empty() || units == "1" ? name : name + " [" + units + "]"; }
};

struct XdmfInformation {
  std::string name, value;
};

struct XdmfGrid {
  std::string name;
  // A regular grid (topology empty): cells per direction x, y, z; origin and spacing in x, y, z.
  std::array<std::size_t, 3> cells{};
  std::array<double, 3> origin{};
  std::array<double, 3> spacing{};
  // An unstructured mesh: "Hexahedron", "Tetrahedron", "Quadrilateral", "Triangle" or "Polyvertex".
  std::string topology;
  std::size_t elements = 0;
  std::size_t nodes_per_element = 0;
  std::size_t nodes = 0;
  std::string connectivity; // "file.h5:/dataset" of elements x nodes_per_element int64
  std::string coordinates;  // "file.h5:/dataset" of nodes x 3 doubles
  std::vector<XdmfField> fields;
  std::vector<XdmfInformation> information;

  static XdmfGrid regular(std::string name, std::array<std::size_t, 3> cells, std::array<double, 3> origin,
                          std::array<double, 3> spacing);
  static XdmfGrid mesh(std::string name, std::string topology, std::size_t elements,
                       std::size_t nodes_per_element, std::string connectivity, std::size_t nodes,
                       std::string coordinates);
  XdmfGrid& add_field(std::string field_name, Center center, std::vector<std::size_t> dims, std::string data,
                      std::string units = "", bool integer = false);
  XdmfGrid& add_information(std::string info_name, std::string value);
};

class XdmfTimeSeries {
 public:
  /// Rank 0 of `comm` writes `path`. add_step, drop_after and resume are collective: a failure to write
  /// the file (RunError) reaches every rank. `name` names the temporal collection and a step's spatial
  /// collection.
  XdmfTimeSeries(MPI_Comm comm, std::filesystem::path path, std::string name = "series");
  /// The grids of one output time: one grid is the time's grid itself; several are a spatial collection.
  void add_step(double time, std::vector<XdmfGrid> grids);
  /// Forgets steps after `time` (a restart from a checkpoint at `time`) and rewrites the file.
  void drop_after(double time);
  /// On a restart: takes over the steps up to `time` from the file the interrupted run left (read by
  /// rank 0; none when there is no file) and rewrites it, so the series goes on from the checkpoint.
  void resume(double time);
  std::string text() const;
  std::size_t steps() const { return steps_.size(); }

 private:
  void write() const;
  std::string step_text(double time, const std::vector<XdmfGrid>& grids) const;
  MPI_Comm comm_;
  bool writer_ = true;
  std::filesystem::path path_;
  std::string name_;
  // Each step's time and its spatial collection as XDMF text (what a resumed series reads back).
  std::vector<std::pair<double, std::string>> steps_;
};

} // namespace ibvalve::io
