#pragma once
// Parallel HDF5 files (MPI-IO through the Open MPI build of HDF5) for fields, meshes and checkpoints.
//
// Every call is collective over the file's communicator. Arrays are global and in C order; on a
// distributed grid each rank writes its own block (write_block), and data held whole on every rank or
// on rank 0 is written once (write_root). Errors become std::runtime_error naming file and dataset.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <hdf5.h>
#include <mpi.h>

namespace ibvalve::io {

class Hdf5File {
 public:
  /// append: an existing file opened to add to (rank 0 of a checkpoint seals it, io/checkpoint.cpp).
  enum class Mode { create, read, append };

  Hdf5File(MPI_Comm comm, const std::filesystem::path& path, Mode mode);
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  /// The global array `name` of shape `global_dims`; this rank writes `data` (C order, shape `count`)
  /// at `offset`. A rank with nothing to write passes count of zeros.
  void write_block(const std::string& name, std::span<const double> data,
                   std::span<const hsize_t> global_dims, std::span<const hsize_t> offset,
                   std::span<const hsize_t> count);
  /// The array `name` of shape `dims`, whose data rank 0 gives (other ranks' `data` is ignored).
  void write_root(const std::string& name, std::span<const double> data, std::span<const hsize_t> dims);
  void write_root(const std::string& name, std::span<const std::int64_t> data, std::span<const hsize_t> dims);
  /// A scalar attribute on the file's root group.
  void write_attribute(const std::string& name, double value);
  double read_attribute(const std::string& name) const;
  void write_string_attribute(const std::string& name, const std::string& value);
  std::string read_string_attribute(const std::string& name) const;
  bool has_attribute(const std::string& name) const;
  /// A string attribute on the dataset or group `object` (a field's `units`, say).
  void write_string_attribute(const std::string& object, const std::string& name, const std::string& value);
  std::string read_string_attribute(const std::string& object, const std::string& name) const;

  /// A 64-bit FNV-1a hash of the file's content as stored: every dataset (name, shape, the bytes of its
  /// values) in name order, then the root attributes but those named in `skip_attributes`. Reads the
  /// whole file; call it on a file opened on one rank (MPI_COMM_SELF).
  std::uint64_t content_hash(std::span<const std::string> skip_attributes) const;

  bool has(const std::string& name) const;
  std::vector<hsize_t> dims(const std::string& name) const;
  /// The whole dataset, on every rank.
  std::vector<double> read(const std::string& name) const;
  std::vector<std::int64_t> read_integers(const std::string& name) const;
  /// This rank's block of a dataset.
  std::vector<double> read_block(const std::string& name, std::span<const hsize_t> offset,
                                 std::span<const hsize_t> count) const;

  const std::filesystem::path& path() const { return path_; }

 private:
  hid_t create_dataset(const std::string& name, hid_t type, std::span<const hsize_t> dims);
  void write_whole(const std::string& name, hid_t type, const void* data, std::span<const hsize_t> dims);
  void read_whole(const std::string& name, hid_t type, void* data) const;

  MPI_Comm comm_;
  int rank_ = 0;
  std::filesystem::path path_;
  hid_t file_ = -1;
};

} // namespace ibvalve::io
