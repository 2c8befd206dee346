#pragma once
// HDF5 files for fields, meshes and checkpoints, over the ranks of a communicator.
//
// Every call is collective over the file's communicator. Arrays are global and in C order; on a
// distributed grid each rank writes its own block (write_block), and data held whole on every rank or
// on rank 0 is written once (write_root). Errors become std::runtime_error naming file and dataset.
//
// A file is read by every rank (MPI-IO), but written by rank 0 alone: the other ranks send it their
// blocks, it builds the file in memory (HDF5's core driver) and close() writes that buffer to disk
// with one checked write, beside its final name, renamed into place. Parallel HDF5 cannot fail a write well:
// after a full disk (ENOSPC) in an MPI-IO write, H5Fclose hangs on 2 ranks and the library crashes at
// exit on 1 (HDF5 1.10), and its error names no OS reason. Here a failed write is one RunError,
// "FILE: cannot write: No space left on device", on every rank, and nothing half-written is left under
// the file's name.
#include <cstdint>
#include <exception>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <hdf5.h>
#include <mpi.h>

namespace ibvalve::io {

class Hdf5File {
 public:
  /// create: written to `path` by close(); memory: built the same way but kept in memory by close()
  /// (rank 0 holds it: image()), a state to go back to without touching the disk; read: an existing file.
  enum class Mode { create, memory, read };

  Hdf5File(MPI_Comm comm, const std::filesystem::path& path, Mode mode);
  /// Reads an image a Mode::memory file left (`root_image`: rank 0's bytes, ignored on the others; every
  /// rank gets a copy). `label` names it in messages. Collective.
  Hdf5File(MPI_Comm comm, const std::string& label, std::span<const char> root_image);
  /// A created file not closed is written here too (errors only logged), unless an exception is
  /// leaving the scope: then nothing is written.
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  /// The global array `name` of shape `global_dims`; this rank writes `data` (C order, shape `count`)
  /// at `offset`. A rank with nothing to write passes count of zeros.
  void write_block(const std::string& name, std::span<const double> data,
                   std::span<const hsize_t> global_dims, std::span<const hsize_t> offset,
                   std::span<const hsize_t> count);
  /// Create mode: writes the file (rank 0, temporary file + rename). Collective: when rank 0 cannot write
  /// it, or any call before failed there, every rank throws (RunError naming the file and the OS reason
  /// for a failed write). Read mode: closes the file.
  void close();

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
  /// whole file; call it on a file opened for reading on one rank (MPI_COMM_SELF), or on a created file,
  /// where rank 0 hashes what it built (the other ranks get 0).
  std::uint64_t content_hash(std::span<const std::string> skip_attributes);

  bool has(const std::string& name) const;
  std::vector<hsize_t> dims(const std::string& name) const;
  /// The whole dataset, on every rank.
  std::vector<double> read(const std::string& name) const;
  std::vector<std::int64_t> read_integers(const std::string& name) const;
  /// This rank's block of a dataset.
  std::vector<double> read_block(const std::string& name, std::span<const hsize_t> offset,
                                 std::span<const hsize_t> count) const;

  const std::filesystem::path& path() const { return path_; }
  /// Mode::memory, after close(): the file's bytes on rank 0 (empty on the other ranks), moved out.
  std::vector<char> take_image() { return std::move(memory_image_); }

 private:
  hid_t create_dataset(const std::string& name, hid_t type, std::span<const hsize_t> dims);
  void write_whole(const std::string& name, hid_t type, const void* data, std::span<const hsize_t> dims);
  void read_whole(const std::string& name, hid_t type, void* data) const;
  /// Create mode: runs `work` on rank 0 (the writer); an exception there is kept for close() to hand to
  /// every rank, and the writer does nothing more, so the ranks stay in step.
  template <class Work>
  void as_writer(Work&& work);
  std::uint64_t hash_content(std::span<const std::string> skip_attributes) const;

  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
  Mode mode_ = Mode::read;
  bool writer_ = false;        // create mode, rank 0
  std::exception_ptr failed_;  // the writer's first failure
  int exceptions_at_open_ = 0; // std::uncaught_exceptions() when constructed
  bool closed_ = false;
  /// The core driver's buffer of a created file (rank 0), held where close() can write it.
  struct CoreImage {
    CoreImage();
    CoreImage(const CoreImage&) = delete;
    CoreImage& operator=(const CoreImage&) = delete;
    H5FD_file_image_callbacks_t callbacks{};
    void* data = nullptr;
    std::size_t size = 0;
  };

  std::filesystem::path path_;
  CoreImage image_;
  std::vector<char> memory_image_; // Mode::memory, after close(), rank 0
  hid_t file_ = -1;
};

} // namespace ibvalve::io
