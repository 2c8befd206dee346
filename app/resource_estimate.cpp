#include "app/resource_estimate.hpp"

#include <cstdio>
#include <limits>

#include <petscsys.h>
#include <unistd.h>

#include <fmt/format.h>

#include "base/errors.hpp"

namespace ibvalve::app {

namespace {

// Bytes measured (peak resident memory, 1 rank, PETSc 3.18; docs/runs.md "Memory") as the slope between
// two grid or mesh sizes, so what every run holds anyway is the per-rank base below.
constexpr double base_per_rank = 100e6;
constexpr double fft_per_cell = 0.57e3;
constexpr double krylov_fft_per_cell = 3.6e3;
constexpr double krylov_amg_per_cell = 5.3e3;
constexpr double nested_per_cell = 9e3;
constexpr double immersed_per_cell = 0.3e3; // the IB's force and velocity fields on the grid
constexpr double per_node = 6e3;
constexpr double per_element = 6e3;

constexpr double gib = 1024.0 * 1024.0 * 1024.0;

/// "23.4 GiB", "310 GiB", "96 MiB".
std::string gib_text(double bytes)
{
  const double g = bytes / gib;
  if (g < 1.0) return fmt::format("{:.0f} MiB", g * 1024.0);
  return g >= 100 ? fmt::format("{:.0f} GiB", g) : fmt::format("{:.1f} GiB", g);
}

/// Physical memory of the machines the ranks run on: each machine's first rank adds its own.
double machine_bytes(MPI_Comm comm)
{
  MPI_Comm node = MPI_COMM_NULL;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int node_rank = 0;
  MPI_Comm_rank(node, &node_rank);
  MPI_Comm_free(&node);
  double own = 0.0;
  if (node_rank == 0)
    own = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  double total = 0.0;
  MPI_Allreduce(&own, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
  return total;
}

} // namespace

double MemoryEstimate::total(int ranks) const
{
  double sum = base_per_rank * ranks;
  for (const MemoryPart& part : parts) sum += part.bytes;
  return sum;
}

MemoryPart fluid_memory(double cells, FluidMemoryKind kind, bool immersed, std::string key)
{
  double per_cell = fft_per_cell;
  if (kind == FluidMemoryKind::krylov_fft) per_cell = krylov_fft_per_cell;
  if (kind == FluidMemoryKind::krylov_amg) per_cell = krylov_amg_per_cell;
  if (kind == FluidMemoryKind::nested) per_cell = nested_per_cell;
  if (immersed) per_cell += immersed_per_cell;
  return {"fluid", cells * per_cell, std::move(key)};
}

MemoryPart structure_memory(double nodes, double elements, std::string key)
{
  return {"structure", nodes * per_node + elements * per_element, std::move(key)};
}

void check_index_count(const io::Config& config, std::string_view key, double count, std::string_view what)
{
  // The grids' and meshes' indices are PetscInt and int: the smaller one bounds every count.
  const double most = static_cast<double>(
      std::min<long long>(std::numeric_limits<PetscInt>::max(), std::numeric_limits<int>::max()));
  if (count > most) {
    config.fail(key, fmt::format("{:.3g} {} is more than the {:.3g} that {}-bit indices hold", count, what,
                                 most, 8 * sizeof(PetscInt)));
  }
}

std::string check_memory(const io::Config& config, const MemoryEstimate& estimate, MPI_Comm comm)
{
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const double machine = machine_bytes(comm);
  io::KeyBinder keys(config);
  MemoryKeys k;
  bind(keys, k);
  const std::string& max_memory = keys.key_of(k.max_memory);
  const double chosen = k.max_memory * gib;
  const double limit = chosen > 0.0 ? chosen : machine;
  const double need = estimate.total(ranks);
  std::string parts;
  const MemoryPart* largest = nullptr;
  for (const MemoryPart& part : estimate.parts) {
    parts += (parts.empty() ? "" : ", ") + part.name + " " + gib_text(part.bytes);
    if (!largest || part.bytes > largest->bytes) largest = &part;
  }
  const std::string limit_text =
      chosen > 0.0 ? max_memory + " is " + gib_text(chosen) : "this machine has " + gib_text(machine);
  if (need > limit && largest)
    config.fail(largest->key,
                "the case needs about " + gib_text(need) + " (" + parts + "); " + limit_text +
                    (chosen > 0.0 ? " (raise it to override)" : " (set " + max_memory + " to override)"));
  return fmt::format("memory: about {} estimated ({}, {}{}); {}", gib_text(need), parts, ranks,
                     (ranks == 1 ? " rank" : " ranks"), limit_text);
}

void bind(io::KeyBinder& keys, MemoryKeys& k)
{
  keys.real("run.max_memory",
            "memory the run may use over all its ranks, in GiB, checked against an estimate "
            "before anything is allocated (docs/runs.md); 0 = the machines' physical memory",
            k.max_memory)
      .defaults(0.0)
      .non_negative();
}

} // namespace ibvalve::app
