#include "io/hdf5.hpp"

#include <numeric>
#include <stdexcept>

namespace ibvalve::io {

namespace {

void check(herr_t status, const std::string& what)
{
  if (status < 0) throw std::runtime_error("HDF5: " + what);
}

hid_t check_id(hid_t id, const std::string& what)
{
  if (id < 0) throw std::runtime_error("HDF5: " + what);
  return id;
}

/// Closes an HDF5 handle when it leaves scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle()
  {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// Creates the groups leading to "a/b/c" (for dataset names with slashes).
void create_parent_groups(hid_t file, const std::string& name)
{
  for (auto slash = name.find('/', 1); slash != std::string::npos; slash = name.find('/', slash + 1)) {
    const std::string group = name.substr(0, slash);
    if (H5Lexists(file, group.c_str(), H5P_DEFAULT) <= 0) {
      Handle g(check_id(H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                        "create group " + group),
               H5Gclose);
    }
  }
}

/// Selects this rank's block [offset, offset + count) of the file space, or nothing when it has none
/// (every rank takes part in a collective transfer, with or without data).
void select_block(hid_t file_space, hid_t memory_space, std::span<const hsize_t> offset,
                  std::span<const hsize_t> count, hsize_t local)
{
  if (local == 0) {
    check(H5Sselect_none(file_space), "select none");
    check(H5Sselect_none(memory_space), "select none");
  } else {
    check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, offset.data(), nullptr, count.data(), nullptr),
          "select block");
  }
}

} // namespace

Hdf5File::Hdf5File(MPI_Comm comm, const std::filesystem::path& path, Mode mode) : comm_(comm), path_(path)
{
  MPI_Comm_rank(comm_, &rank_);
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  check(H5Pset_fapl_mpio(access, comm_, MPI_INFO_NULL), "set MPI-IO");
  if (mode == Mode::create)
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access);
  else
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, access);
  check_id(file_, (mode == Mode::create ? "cannot create " : "cannot open ") + path.string());
}

Hdf5File::~Hdf5File()
{
  if (file_ >= 0) H5Fclose(file_);
}

hid_t Hdf5File::create_dataset(const std::string& name, hid_t type, std::span<const hsize_t> dims)
{
  create_parent_groups(file_, name);
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  return check_id(H5Dcreate2(file_, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  "create dataset " + name + " in " + path_.string());
}

void Hdf5File::write_block(const std::string& name, std::span<const double> data,
                           std::span<const hsize_t> global_dims, std::span<const hsize_t> offset,
                           std::span<const hsize_t> count)
{
  const hsize_t local = std::accumulate(count.begin(), count.end(), hsize_t{1}, std::multiplies<>());
  if (local != data.size())
    throw std::logic_error("Hdf5File::write_block: data size does not match count for " + name);
  Handle dataset(create_dataset(name, H5T_NATIVE_DOUBLE, global_dims), H5Dclose);
  Handle file_space(H5Dget_space(dataset), H5Sclose);
  Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose);
  select_block(file_space, memory_space, offset, count, local);
  Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  check(H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE), "collective transfer");
  check(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory_space, file_space, transfer, data.data()),
        "write " + name + " to " + path_.string());
}

void Hdf5File::write_whole(const std::string& name, hid_t type, const void* data,
                           std::span<const hsize_t> dims)
{
  Handle dataset(create_dataset(name, type, dims), H5Dclose);
  Handle file_space(H5Dget_space(dataset), H5Sclose);
  Handle memory_space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  if (rank_ != 0) {
    check(H5Sselect_none(file_space), "select none");
    check(H5Sselect_none(memory_space), "select none");
  }
  Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  check(H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE), "collective transfer");
  check(H5Dwrite(dataset, type, memory_space, file_space, transfer, data),
        "write " + name + " to " + path_.string());
}

void Hdf5File::write_root(const std::string& name, std::span<const double> data,
                          std::span<const hsize_t> dims)
{
  const hsize_t n = std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
  if (rank_ == 0 && n != data.size())
    throw std::logic_error("Hdf5File::write_root: size mismatch for " + name);
  write_whole(name, H5T_NATIVE_DOUBLE, data.data(), dims);
}

void Hdf5File::write_root(const std::string& name, std::span<const std::int64_t> data,
                          std::span<const hsize_t> dims)
{
  const hsize_t n = std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
  if (rank_ == 0 && n != data.size())
    throw std::logic_error("Hdf5File::write_root: size mismatch for " + name);
  write_whole(name, H5T_NATIVE_INT64, data.data(), dims);
}

void Hdf5File::write_attribute(const std::string& name, double value)
{
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attribute(
      check_id(H5Acreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT),
               "create attribute " + name),
      H5Aclose);
  check(H5Awrite(attribute, H5T_NATIVE_DOUBLE, &value), "write attribute " + name);
}

double Hdf5File::read_attribute(const std::string& name) const
{
  Handle attribute(
      check_id(H5Aopen(file_, name.c_str(), H5P_DEFAULT), "no attribute " + name + " in " + path_.string()),
      H5Aclose);
  double value = 0;
  check(H5Aread(attribute, H5T_NATIVE_DOUBLE, &value), "read attribute " + name);
  return value;
}

bool Hdf5File::has(const std::string& name) const
{
  return H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0;
}

std::vector<hsize_t> Hdf5File::dims(const std::string& name) const
{
  Handle dataset(
      check_id(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), "no dataset " + name + " in " + path_.string()),
      H5Dclose);
  Handle space(H5Dget_space(dataset), H5Sclose);
  std::vector<hsize_t> d(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, d.data(), nullptr);
  return d;
}

void Hdf5File::read_whole(const std::string& name, hid_t type, void* data) const
{
  Handle dataset(
      check_id(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), "no dataset " + name + " in " + path_.string()),
      H5Dclose);
  check(H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "read " + name);
}

std::vector<double> Hdf5File::read(const std::string& name) const
{
  const auto d = dims(name);
  std::vector<double> out(std::accumulate(d.begin(), d.end(), hsize_t{1}, std::multiplies<>()));
  read_whole(name, H5T_NATIVE_DOUBLE, out.data());
  return out;
}

std::vector<std::int64_t> Hdf5File::read_integers(const std::string& name) const
{
  const auto d = dims(name);
  std::vector<std::int64_t> out(std::accumulate(d.begin(), d.end(), hsize_t{1}, std::multiplies<>()));
  read_whole(name, H5T_NATIVE_INT64, out.data());
  return out;
}

std::vector<double> Hdf5File::read_block(const std::string& name, std::span<const hsize_t> offset,
                                         std::span<const hsize_t> count) const
{
  Handle dataset(
      check_id(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), "no dataset " + name + " in " + path_.string()),
      H5Dclose);
  Handle file_space(H5Dget_space(dataset), H5Sclose);
  const hsize_t local = std::accumulate(count.begin(), count.end(), hsize_t{1}, std::multiplies<>());
  std::vector<double> out(local);
  Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose);
  select_block(file_space, memory_space, offset, count, local);
  check(H5Dread(dataset, H5T_NATIVE_DOUBLE, memory_space, file_space, H5P_DEFAULT, out.data()),
        "read " + name);
  return out;
}

} // namespace ibvalve::io
