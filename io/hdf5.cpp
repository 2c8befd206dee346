#include "io/hdf5.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <numeric>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "base/logger.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"

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

// The core driver's buffer, allocated through these callbacks so that close() can write it in place.
Hdf5File::CoreImage::CoreImage()
{
  callbacks.image_malloc = [](std::size_t size, H5FD_file_image_op_t, void* udata) -> void* {
    auto* image = static_cast<CoreImage*>(udata);
    image->data = std::malloc(size);
    image->size = image->data ? size : 0;
    return image->data;
  };
  callbacks.image_memcpy = [](void* dest, const void* src, std::size_t size, H5FD_file_image_op_t,
                              void*) -> void* { return std::memcpy(dest, src, size); };
  callbacks.image_realloc = [](void* old, std::size_t size, H5FD_file_image_op_t, void* udata) -> void* {
    auto* image = static_cast<CoreImage*>(udata);
    void* grown = std::realloc(old, size);
    if (grown != nullptr) {
      image->data = grown;
      image->size = size;
    }
    return grown;
  };
  callbacks.image_free = [](void* buffer, H5FD_file_image_op_t, void* udata) -> herr_t {
    auto* image = static_cast<CoreImage*>(udata);
    if (buffer == image->data) {
      image->data = nullptr;
      image->size = 0;
    }
    std::free(buffer);
    return 0;
  };
  // HDF5 copies the property list (and its udata) into the file: every copy is this same image.
  callbacks.udata_copy = [](void* udata) -> void* { return udata; };
  callbacks.udata_free = [](void*) -> herr_t { return 0; };
  callbacks.udata = this;
}

Hdf5File::Hdf5File(MPI_Comm comm, const std::filesystem::path& path, Mode mode)
    : comm_(comm), mode_(mode), exceptions_at_open_(std::uncaught_exceptions()), path_(path)
{
  // Every failing call is checked and becomes one exception naming file and dataset: HDF5's own
  // error stacks (ten lines per failure, e.g. for a torn checkpoint passed over) are not printed.
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  if (mode == Mode::read) {
    Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    check(H5Pset_fapl_mpio(access, comm_, MPI_INFO_NULL), "set MPI-IO");
    file_ = check_id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access), "cannot open " + path.string());
    return;
  }
  writer_ = rank_ == 0;
  as_writer([&] {
    // In memory, grown 256 KiB at a time (realloc), never backed by the disk: close() writes it.
    Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    check(H5Pset_fapl_core(access, std::size_t{1} << 18, 0), "set the core driver");
    check(H5Pset_file_image_callbacks(access, &image_.callbacks), "set the image callbacks");
    file_ = check_id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access),
                     "cannot create " + path.string());
  });
}

Hdf5File::Hdf5File(MPI_Comm comm, const std::string& label, std::span<const char> root_image)
    : comm_(comm), mode_(Mode::read), exceptions_at_open_(std::uncaught_exceptions()), path_(label)
{
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  // Every rank opens its own copy with the core driver: reads are independent (H5P_DEFAULT transfers).
  std::uint64_t size = rank_ == 0 ? root_image.size() : 0;
  MPI_Bcast(&size, 1, MPI_UINT64_T, 0, comm_);
  if (size == 0) throw std::logic_error("Hdf5File: " + label + " has no image");
  std::vector<char> bytes(size);
  if (rank_ == 0) std::copy(root_image.begin(), root_image.end(), bytes.begin());
  constexpr std::uint64_t chunk = std::uint64_t{1} << 30; // MPI counts are int
  for (std::uint64_t at = 0; at < size; at += chunk)
    MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(chunk, size - at)), MPI_CHAR, 0, comm_);
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  check(H5Pset_fapl_core(access, std::size_t{1} << 18, 0), "set the core driver");
  check(H5Pset_file_image(access, bytes.data(), bytes.size()), "set the image of " + label); // copied
  file_ = check_id(H5Fopen(label.c_str(), H5F_ACC_RDONLY, access), "cannot open the image of " + label);
}

Hdf5File::~Hdf5File()
{
  if (mode_ != Mode::read && !closed_ && std::uncaught_exceptions() == exceptions_at_open_) {
    try {
      close();
    } catch (const std::exception& e) {
      base::Logger::global().error(e.what());
    }
  }
  if (file_ >= 0) H5Fclose(file_);
}

template <class Work>
void Hdf5File::as_writer(Work&& work)
{
  if (mode_ == Mode::read) throw std::logic_error("Hdf5File: " + path_.string() + " is open for reading");
  if (!writer_ || failed_) return;
  try {
    work();
  } catch (...) {
    failed_ = std::current_exception();
  }
}

void Hdf5File::close()
{
  if (closed_) return;
  closed_ = true;
  if (mode_ == Mode::read) {
    if (file_ >= 0) H5Fclose(file_);
    file_ = -1;
    return;
  }
  as_writer([&] {
    check(H5Fflush(file_, H5F_SCOPE_LOCAL), "flush " + path_.string());
    const ssize_t size = H5Fget_file_image(file_, nullptr, 0);
    if (size < 0 || image_.data == nullptr || static_cast<std::size_t>(size) > image_.size)
      throw std::runtime_error("HDF5: no image of " + path_.string());
    // Written from the driver's own buffer: a copy (H5Fget_file_image) would double the memory the
    // file takes at its largest (4.4 MB more for the default valve case's checkpoint).
    const char* bytes = static_cast<const char*>(image_.data);
    if (mode_ == Mode::memory)
      memory_image_.assign(bytes, bytes + size);
    else
      write_file_atomically(path_, std::string_view(bytes, size));
    H5Fclose(file_);
    file_ = -1;
  });
  if (file_ >= 0) H5Fclose(file_);
  file_ = -1;
  rethrow_on_every_rank(comm_, failed_);
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
  if (mode_ == Mode::read) throw std::logic_error("Hdf5File: " + path_.string() + " is open for reading");
  // The writer gathers every rank's block (where it goes, then its values) and writes them in turn.
  const std::size_t ndims = count.size();
  std::vector<unsigned long long> place(2 * ndims), places(writer_ ? 2 * ndims * size_ : 0);
  std::copy(offset.begin(), offset.end(), place.begin());
  std::copy(count.begin(), count.end(), place.begin() + static_cast<std::ptrdiff_t>(ndims));
  MPI_Gather(place.data(), static_cast<int>(place.size()), MPI_UNSIGNED_LONG_LONG, places.data(),
             static_cast<int>(place.size()), MPI_UNSIGNED_LONG_LONG, 0, comm_);
  const int mine = static_cast<int>(local);
  std::vector<int> sizes(writer_ ? size_ : 0), starts(writer_ ? size_ : 0);
  MPI_Gather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, comm_);
  if (writer_) std::exclusive_scan(sizes.begin(), sizes.end(), starts.begin(), 0);
  std::vector<double> all(writer_ ? static_cast<std::size_t>(std::accumulate(sizes.begin(), sizes.end(), 0))
                                  : 0);
  MPI_Gatherv(data.data(), mine, MPI_DOUBLE, all.data(), sizes.data(), starts.data(), MPI_DOUBLE, 0, comm_);
  as_writer([&] {
    Handle dataset(create_dataset(name, H5T_NATIVE_DOUBLE, global_dims), H5Dclose);
    Handle file_space(H5Dget_space(dataset), H5Sclose);
    for (int r = 0; r < size_; ++r) {
      if (sizes[r] == 0) continue;
      const std::vector<hsize_t> at(places.begin() + 2 * ndims * r, places.begin() + 2 * ndims * r + ndims);
      const std::vector<hsize_t> block(places.begin() + 2 * ndims * r + ndims,
                                       places.begin() + 2 * ndims * (r + 1));
      Handle memory_space(H5Screate_simple(static_cast<int>(ndims), block.data(), nullptr), H5Sclose);
      check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, at.data(), nullptr, block.data(), nullptr),
            "select block");
      check(
          H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory_space, file_space, H5P_DEFAULT, all.data() + starts[r]),
          "write " + name + " to " + path_.string());
    }
  });
}

void Hdf5File::write_whole(const std::string& name, hid_t type, const void* data,
                           std::span<const hsize_t> dims)
{
  as_writer([&] {
    Handle dataset(create_dataset(name, type, dims), H5Dclose);
    check(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "write " + name + " to " + path_.string());
  });
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
  as_writer([&] {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle attribute(
        check_id(H5Acreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT),
                 "create attribute " + name),
        H5Aclose);
    check(H5Awrite(attribute, H5T_NATIVE_DOUBLE, &value), "write attribute " + name);
  });
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

namespace {

void write_string_attribute_at(hid_t location, const std::string& name, const std::string& value)
{
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  check(H5Tset_size(type, std::max<std::size_t>(value.size(), 1)), "string type");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attribute(check_id(H5Acreate2(location, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
                            "create attribute " + name),
                   H5Aclose);
  std::string padded = value.empty() ? std::string(1, '\0') : value;
  check(H5Awrite(attribute, type, padded.data()), "write attribute " + name);
}

std::string read_string_attribute_at(hid_t location, const std::string& name, const std::string& where)
{
  Handle attribute(
      check_id(H5Aopen(location, name.c_str(), H5P_DEFAULT), "no attribute " + name + " in " + where),
      H5Aclose);
  Handle type(H5Aget_type(attribute), H5Tclose);
  if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0)
    throw std::runtime_error("HDF5: attribute " + name + " in " + where + " is not a string");
  std::string value(H5Tget_size(type), '\0');
  check(H5Aread(attribute, type, value.data()), "read attribute " + name);
  return value.substr(0, value.find('\0'));
}

} // namespace

void Hdf5File::write_string_attribute(const std::string& name, const std::string& value)
{
  as_writer([&] { write_string_attribute_at(file_, name, value); });
}

void Hdf5File::write_string_attribute(const std::string& object, const std::string& name,
                                      const std::string& value)
{
  // Rank 0 builds the file (as_writer); the other ranks hold no handle to it.
  as_writer([&] {
    Handle target(
        check_id(H5Oopen(file_, object.c_str(), H5P_DEFAULT), "no " + object + " in " + path_.string()),
        H5Oclose);
    write_string_attribute_at(target, name, value);
  });
}

std::string Hdf5File::read_string_attribute(const std::string& object, const std::string& name) const
{
  Handle target(
      check_id(H5Oopen(file_, object.c_str(), H5P_DEFAULT), "no " + object + " in " + path_.string()),
      H5Oclose);
  return read_string_attribute_at(target, name, path_.string() + ":/" + object);
}

std::string Hdf5File::read_string_attribute(const std::string& name) const
{
  return read_string_attribute_at(file_, name, path_.string());
}

bool Hdf5File::has_attribute(const std::string& name) const
{
  return H5Aexists(file_, name.c_str()) > 0;
}

namespace {

struct Fnv1a {
  std::uint64_t value = 14695981039346656037ull;
  void add(const void* data, std::size_t size)
  {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      value ^= bytes[i];
      value *= 1099511628211ull;
    }
  }
  void add(const std::string& text) { add(text.data(), text.size() + 1); }
};

herr_t collect_dataset(hid_t, const char* name, const H5O_info_t* info, void* names)
{
  if (info->type == H5O_TYPE_DATASET) static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

herr_t collect_attribute(hid_t, const char* name, const H5A_info_t*, void* names)
{
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

} // namespace

std::uint64_t Hdf5File::content_hash(std::span<const std::string> skip_attributes)
{
  if (mode_ == Mode::read) return hash_content(skip_attributes);
  std::uint64_t value = 0;
  as_writer([&] { value = hash_content(skip_attributes); });
  return value;
}

std::uint64_t Hdf5File::hash_content(std::span<const std::string> skip_attributes) const
{
  Fnv1a hash;
  std::vector<std::string> datasets;
  check(H5Ovisit2(file_, H5_INDEX_NAME, H5_ITER_INC, collect_dataset, &datasets, H5O_INFO_BASIC),
        "list the datasets of " + path_.string());
  for (const std::string& name : datasets) {
    Handle dataset(check_id(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), "open " + name), H5Dclose);
    Handle stored(H5Dget_type(dataset), H5Tclose);
    Handle type(check_id(H5Tget_native_type(stored, H5T_DIR_ASCEND), "type of " + name), H5Tclose);
    const auto shape = dims(name);
    const hsize_t count = std::accumulate(shape.begin(), shape.end(), hsize_t{1}, std::multiplies<>());
    std::vector<unsigned char> bytes(count * H5Tget_size(type));
    if (!bytes.empty())
      check(H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()),
            "read " + name + " from " + path_.string());
    hash.add(name);
    hash.add(shape.data(), shape.size() * sizeof(hsize_t));
    hash.add(bytes.data(), bytes.size());
  }
  std::vector<std::string> attributes;
  hsize_t position = 0;
  check(H5Aiterate2(file_, H5_INDEX_NAME, H5_ITER_INC, &position, collect_attribute, &attributes),
        "list the attributes of " + path_.string());
  for (const std::string& name : attributes) {
    if (std::find(skip_attributes.begin(), skip_attributes.end(), name) != skip_attributes.end()) continue;
    Handle attribute(check_id(H5Aopen(file_, name.c_str(), H5P_DEFAULT), "open attribute " + name), H5Aclose);
    Handle stored(H5Aget_type(attribute), H5Tclose);
    Handle type(check_id(H5Tget_native_type(stored, H5T_DIR_ASCEND), "type of " + name), H5Tclose);
    std::vector<unsigned char> bytes(H5Tget_size(type));
    check(H5Aread(attribute, type, bytes.data()), "read attribute " + name);
    hash.add(name);
    hash.add(bytes.data(), bytes.size());
  }
  return hash.value;
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
