#include "fluid/composite_velocity.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>
#include <string>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {

// Keys pack level (4 bits), normal (2 bits) and the three indices shifted by 16 (19 bits each).
constexpr PetscInt index_shift = 16;
std::uint64_t pack(const FaceKey& k)
{
  std::uint64_t key = static_cast<std::uint64_t>(k.level) << 59 | static_cast<std::uint64_t>(k.normal) << 57;
  for (int d = 0; d < 3; ++d) key |= static_cast<std::uint64_t>(k.index[d] + index_shift) << (19 * d);
  return key;
}

/// Lagrange weights of the nodes `s` at `x`.
std::vector<double> lagrange(const std::vector<double>& s, double x)
{
  std::vector<double> w(s.size(), 1.0);
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = 0; j < s.size(); ++j)
      if (j != i) w[i] *= (x - s[j]) / (s[i] - s[j]);
  return w;
}

} // namespace

/// Windows of consecutive sample indices in [0, top] around the position s (in sample units), best first:
/// the three nearest (centred), the other three holding s, those shifted inside [0, top] (one-sided near a
/// wall, extrapolating by less than a cell), then two points, then one.
std::vector<std::vector<PetscInt>> sample_windows(double s, PetscInt top)
{
  const PetscInt k0 = static_cast<PetscInt>(std::floor(s));
  std::vector<PetscInt> starts = {k0 - 1, k0};
  if (s - static_cast<double>(k0) > 0.5) std::swap(starts[0], starts[1]);
  std::vector<std::vector<PetscInt>> out;
  auto push = [&](std::vector<PetscInt> w) {
    if (w.front() < 0 || w.back() > top) return;
    for (const auto& v : out)
      if (v == w) return;
    out.push_back(std::move(w));
  };
  for (const PetscInt a : starts) push({a, a + 1, a + 2});
  for (const PetscInt a : starts) {
    const PetscInt b = std::clamp<PetscInt>(a, 0, top - 2);
    push({b, b + 1, b + 2});
  }
  const PetscInt b = std::clamp<PetscInt>(k0, 0, top - 1);
  push({b, b + 1});
  push({std::clamp<PetscInt>(static_cast<PetscInt>(std::lround(s)), 0, top)});
  return out;
}

namespace {

Index3 unit(int d)
{
  Index3 e{0, 0, 0};
  e[d] = 1;
  return e;
}
Index3 plus(Index3 a, const Index3& b, PetscInt s = 1)
{
  for (int d = 0; d < 3; ++d) a[d] += s * b[d];
  return a;
}

} // namespace

void FaceValue::compress()
{
  auto merge = [](std::vector<std::pair<PetscInt, double>>& terms) {
    std::sort(terms.begin(), terms.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::size_t out = 0;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      if (out > 0 && terms[out - 1].first == terms[i].first)
        terms[out - 1].second += terms[i].second;
      else
        terms[out++] = terms[i];
    }
    terms.resize(out);
  };
  merge(unknowns);
  merge(data);
}

void FaceValue::add(const FaceValue& other, double weight)
{
  if (weight == 0.0) return;
  for (const auto& [i, w] : other.unknowns) unknowns.emplace_back(i, weight * w);
  for (const auto& [i, w] : other.data) data.emplace_back(i, weight * w);
}

CompositeVelocity::CompositeVelocity(const CompositeOperators& operators) : operators_(&operators)
{
  const PetscInt faces = number_faces();
  const PetscInt begin = find_owned_keys(faces);
  // The face values are memoised as the two stencils ask for them, which numbers the wall data points:
  // the Laplacian's first, then the convection's.
  assemble_laplacian(begin);
  build_convection_stencils();
  const petsc::OwnedVec probe = operators.create_face_vector();
  PETSC_CHECK(VecScatterCreateToAll(probe, gather_.out(), gathered_.out()));
}

PetscInt CompositeVelocity::number_faces()
{
  const GridHierarchy& h = hierarchy();
  const CompositeOperators& operators = *operators_;
  const CompositeCells& cells = operators.cells();
  // The face numbering of CompositeOperators (Neumann sides): each rank enumerates the faces of its cells
  // in cell order, so the global order is that enumeration over all cells. Replayed here on every rank.
  PetscInt next = 0;
  cells.for_each(0, cells.size(), [&](PetscInt, const CompositeCells::Cell& cell) {
    const int l = cell.level;
    for (int d = 0; d < 3; ++d)
      for (const int side : {-1, 1}) {
        Index3 neighbour = cell.index;
        neighbour[d] += side;
        if (!h.domain_box(l).contains(neighbour) &&
            !operators.boundary_face(l, cell.index, side_index(d, side > 0)))
          continue;
        if (h.domain_box(l).contains(neighbour) && h.box_containing(l, neighbour) >= 0 &&
            (side > 0 || h.covered(l, neighbour)))
          continue;
        FaceKey key{l, d, cell.index};
        if (side > 0) ++key.index[d];
        indices_[pack(key)] = next++;
      }
  });
  return next;
}

PetscInt CompositeVelocity::find_owned_keys(PetscInt faces)
{
  const GridHierarchy& h = hierarchy();
  const auto& owned = operators_->owned_faces();
  PetscInt begin = 0;
  {
    const PetscInt local = static_cast<PetscInt>(owned.size());
    PetscInt end = 0;
    MPI_Scan(&local, &end, 1, MPIU_INT, MPI_SUM, operators_->comm());
    begin = end - local;
  }
  // Owned keys in the operators' order (checked against their face centres).
  std::vector<FaceKey> all(static_cast<std::size_t>(faces));
  for (const auto& [packed, n] : indices_) {
    FaceKey k;
    k.level = static_cast<int>(packed >> 59);
    k.normal = static_cast<int>((packed >> 57) & 3u);
    for (int d = 0; d < 3; ++d)
      k.index[d] = static_cast<PetscInt>((packed >> (19 * d)) & ((1u << 19) - 1)) - index_shift;
    all[static_cast<std::size_t>(n)] = k;
  }
  for (std::size_t f = 0; f < owned.size(); ++f) {
    const FaceKey& k = all[static_cast<std::size_t>(begin) + f];
    const Real3 x = position(k);
    double off = 0.0;
    for (int d = 0; d < 3; ++d) off = std::max(off, std::abs(x[d] - owned[f].center[d]));
    if (k.normal != owned[f].normal || off > 1e-9 * h.domain().length(0))
      throw std::logic_error("composite velocity: face numbering differs from CompositeOperators");
    owned_keys_.push_back(k);
  }
  return begin;
}

void CompositeVelocity::assemble_laplacian(PetscInt begin)
{
  const GridHierarchy& h = hierarchy();
  // The Laplacian: sum over directions of (u(I+e) - 2 u(I) + u(I-e)) / h_e^2, ghosts resolved.
  const PetscInt local = static_cast<PetscInt>(owned_keys_.size());
  std::vector<FaceValue> rows(owned_keys_.size());
  laplacian_data_.resize(owned_keys_.size());
  std::vector<PetscInt> diagonal_count(owned_keys_.size(), 0), off_count(owned_keys_.size(), 0);
  const PetscInt end = begin + local;
  for (std::size_t f = 0; f < owned_keys_.size(); ++f) {
    const FaceKey& k = owned_keys_[f];
    FaceValue& row = rows[f];
    for (int e = 0; e < 3; ++e) {
      const double w = 1.0 / (h.h(k.level, e) * h.h(k.level, e));
      row.add(value({k.level, k.normal, plus(k.index, unit(e))}), w);
      row.add(value({k.level, k.normal, plus(k.index, unit(e), -1)}), w);
      row.add(value(k), -2.0 * w);
    }
    row.compress();
    for (const auto& [c, w] : row.unknowns) ++(c >= begin && c < end ? diagonal_count[f] : off_count[f]);
    laplacian_data_[f] = row.data;
  }
  PETSC_CHECK(MatCreateAIJ(operators_->comm(), local, local, PETSC_DETERMINE, PETSC_DETERMINE, 0,
                           diagonal_count.data(), 0, off_count.data(), laplacian_.out()));
  for (std::size_t f = 0; f < owned_keys_.size(); ++f) {
    std::vector<PetscInt> columns;
    std::vector<PetscScalar> values;
    for (const auto& [c, w] : rows[f].unknowns) {
      columns.push_back(c);
      values.push_back(w);
    }
    const PetscInt global_row = begin + static_cast<PetscInt>(f);
    PETSC_CHECK(MatSetValues(laplacian_, 1, &global_row, static_cast<PetscInt>(columns.size()),
                             columns.data(), values.data(), INSERT_VALUES));
  }
  PETSC_CHECK(MatAssemblyBegin(laplacian_, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(laplacian_, MAT_FINAL_ASSEMBLY));
}

void CompositeVelocity::build_convection_stencils()
{
  // Convection stencils: for face (l, d, I) and each direction e, the d-values at I +- e and the e-values
  // at the edges +- e/2 (faces I + e, I + e - e_d and I, I - e_d normal to e).
  std::unordered_map<std::uint64_t, std::int32_t> slot;
  std::vector<const FaceValue*> read;
  auto slot_of = [&](const FaceKey& key) {
    const auto [it, inserted] = slot.try_emplace(pack(key), static_cast<std::int32_t>(read.size()));
    if (inserted) read.push_back(&value(key)); // memoised: the reference stays valid
    return it->second;
  };
  for (const FaceKey& k : owned_keys_) {
    std::array<std::int32_t, 24> s{};
    const int d = k.normal;
    for (int e = 0; e < 3; ++e) {
      const Index3 I = k.index, ee = unit(e), ed = unit(d);
      s[8 * e + 0] = slot_of({k.level, d, plus(I, ee, -2)});
      s[8 * e + 1] = slot_of({k.level, d, plus(I, ee, -1)});
      s[8 * e + 2] = slot_of({k.level, d, plus(I, ee)});
      s[8 * e + 3] = slot_of({k.level, d, plus(I, ee, 2)});
      s[8 * e + 4] = slot_of({k.level, e, plus(I, ee)});               // +e/2 edge, upper d side
      s[8 * e + 5] = slot_of({k.level, e, plus(plus(I, ee), ed, -1)}); // +e/2 edge, lower d side
      s[8 * e + 6] = slot_of({k.level, e, I});                         // -e/2 edge, upper d side
      s[8 * e + 7] = slot_of({k.level, e, plus(I, ed, -1)});           // -e/2 edge, lower d side
    }
    convection_stencils_.push_back(s);
  }
  convection_values_ = FaceValueTable(read);
  convection_buffer_.resize(convection_values_.size());
}

CompositeVelocity::Kind CompositeVelocity::classify(const FaceKey& k) const
{
  const GridHierarchy& h = hierarchy();
  const Index3& n = h.domain_cells(k.level);
  const int d = k.normal;
  for (int e = 0; e < 3; ++e) {
    const PetscInt top = e == d ? n[e] : n[e] - 1;
    if (k.index[e] < 0 || k.index[e] > top) return Kind::outside_domain;
  }
  Index3 lower = k.index;
  --lower[d];
  if (k.index[d] == 0 || k.index[d] == n[d]) {
    // A boundary face: an unknown (or fine/coarse data, like any face) where the pressure is given, a wall
    // otherwise.
    const bool upper = k.index[d] == n[d];
    const Index3& inside = upper ? lower : k.index;
    if (!operators_->boundary_face(k.level, inside, side_index(d, upper))) return Kind::wall;
    if (h.box_containing(k.level, inside) < 0) return Kind::outside_level;
    return h.covered(k.level, inside) ? Kind::covered : Kind::unknown;
  }
  const bool in_lower = h.box_containing(k.level, lower) >= 0,
             in_upper = h.box_containing(k.level, k.index) >= 0;
  if (!in_lower && !in_upper) return Kind::outside_level;
  if ((in_lower && h.covered(k.level, lower)) || (in_upper && h.covered(k.level, k.index)))
    return Kind::covered;
  return Kind::unknown;
}

PetscInt CompositeVelocity::index(const FaceKey& key) const
{
  const auto it = indices_.find(pack(key));
  return it == indices_.end() ? -1 : it->second;
}

Real3 CompositeVelocity::position(const FaceKey& k) const
{
  const GridHierarchy& h = hierarchy();
  Real3 x = h.cell_center(k.level, k.index);
  x[k.normal] -= 0.5 * h.h(k.level, k.normal);
  return x;
}

PetscInt CompositeVelocity::data_point(const Real3& x, int component) const
{
  // Wall points are found again by their position (rounded to 1e-9 of the finest spacing).
  const GridHierarchy& h = hierarchy();
  std::uint64_t key = static_cast<std::uint64_t>(component) << 62;
  for (int d = 0; d < 3; ++d) {
    const double s = (x[d] - h.domain().lower[d]) / h.h(h.finest(), d);
    key ^= static_cast<std::uint64_t>(std::llround(s * 4.0) + 1000) << (20 * d);
  }
  const auto [it, inserted] = data_index_.try_emplace(key, static_cast<PetscInt>(data_points_.size()));
  if (inserted) data_points_.push_back({x, component});
  return it->second;
}

const FaceValue& CompositeVelocity::value(const FaceKey& key) const
{
  const std::uint64_t packed = pack(key);
  if (const auto it = values_.find(packed); it != values_.end()) return it->second;
  FaceValue v = compute(key);
  v.compress();
  return values_.emplace(packed, std::move(v)).first->second;
}

FaceValue CompositeVelocity::compute(const FaceKey& k) const
{
  const GridHierarchy& h = hierarchy();
  FaceValue v;
  switch (classify(k)) {
  case Kind::unknown:
    v.unknowns.emplace_back(index(k), 1.0);
    return v;
  case Kind::wall:
    v.data.emplace_back(data_point(position(k), k.normal), 1.0);
    return v;
  case Kind::covered:
    return interpolate(k.level + 1, k.normal, position(k), Mode::finer_interior);
  case Kind::outside_level:
    return interpolate(k.level - 1, k.normal, position(k), Mode::coarser);
  case Kind::outside_domain:
    break;
  }
  // Outside a wall: quadratic extrapolation through the wall value (the convective term's upwind stencil
  // reaches two faces out, the Laplacian one).
  const Index3& n = h.domain_cells(k.level);
  const int d = k.normal;
  if (k.index[d] < 0 || k.index[d] > n[d]) {
    const bool low = k.index[d] < 0;
    FaceKey wall = k, u1 = k, u2 = k;
    wall.index[d] = low ? 0 : n[d];
    FaceKey on_side = wall; // the side's face at the nearest tangential position inside the domain
    for (int t = 0; t < 3; ++t)
      if (t != d) on_side.index[t] = std::clamp<PetscInt>(on_side.index[t], 0, n[t] - 1);
    if (classify(on_side) != Kind::wall) {
      // Beyond a traction face: du_n/dn = 0 there, the normal component is even about the side.
      FaceKey mirror = k;
      mirror.index[d] = low ? -k.index[d] : 2 * n[d] - k.index[d];
      v.add(value(mirror), 1.0);
      return v;
    }
    // Normal component beyond a wall: the quadratic through the wall face and the next two, at -h.
    if (k.index[d] != -1 && k.index[d] != n[d] + 1)
      throw std::logic_error("composite velocity: a ghost more than one face beyond a wall");
    u1.index[d] = low ? 1 : n[d] - 1;
    u2.index[d] = low ? 2 : n[d] - 2;
    v.add(value(wall), 3.0);
    v.add(value(u1), -3.0);
    v.add(value(u2), 1.0);
    return v;
  }
  for (int t = 0; t < 3; ++t) {
    if (t == d || (k.index[t] >= 0 && k.index[t] < n[t])) continue;
    // Tangential component half a cell (1.5 cells) outside: the quadratic through the wall value g and the
    // first two faces inside, (8 g - 6 u_1 + u_2)/3 (8 g - 9 u_1 + 2 u_2).
    const bool low = k.index[t] < 0;
    const PetscInt out = low ? -k.index[t] : k.index[t] - n[t] + 1; // 1 or 2 faces out
    if (out > 2) throw std::logic_error("composite velocity: a ghost more than two cells outside the domain");
    FaceKey u1 = k, u2 = k;
    u1.index[t] = low ? 0 : n[t] - 1;
    u2.index[t] = low ? 1 : n[t] - 2;
    Real3 wall = position(k);
    wall[t] = low ? h.domain().lower[t] : h.domain().upper[t];
    const std::array<double, 3> w =
        out == 1 ? std::array<double, 3>{8.0 / 3.0, -2.0, 1.0 / 3.0} : std::array<double, 3>{8.0, -9.0, 2.0};
    v.data.emplace_back(data_point(wall, d), w[0]);
    v.add(value(u1), w[1]);
    v.add(value(u2), w[2]);
    return v;
  }
  throw std::logic_error("composite velocity: unclassified face");
}

FaceValue CompositeVelocity::interpolate(int level, int normal, const Real3& x, Mode mode) const
{
  const GridHierarchy& h = hierarchy();
  const Index3& n = h.domain_cells(level);
  // Candidate windows of sample indices per direction, best first.
  std::array<std::vector<std::vector<PetscInt>>, 3> windows;
  std::array<double, 3> target{};
  for (int e = 0; e < 3; ++e) {
    const double offset = e == normal ? 0.0 : 0.5;
    const double s = (x[e] - h.domain().lower[e]) / h.h(level, e) - offset;
    target[e] = s;
    const PetscInt top = e == normal ? n[e] : n[e] - 1;
    const double nearest = std::round(s);
    if (std::abs(s - nearest) < 1e-8) {
      windows[e].push_back({static_cast<PetscInt>(nearest)});
      continue;
    }
    windows[e] = sample_windows(s, top);
  }
  auto allowed = [&](Kind kind, bool relaxed) {
    if (kind == Kind::unknown || kind == Kind::wall || kind == Kind::covered) return true;
    return relaxed && mode == Mode::coarser && kind == Kind::outside_level;
  };
  for (const bool relaxed : {false, true}) {
    for (const auto& wx : windows[0])
      for (const auto& wy : windows[1])
        for (const auto& wz : windows[2]) {
          bool ok = true;
          for (const PetscInt i : wx)
            for (const PetscInt j : wy)
              for (const PetscInt k : wz)
                if (ok && !allowed(classify({level, normal, {i, j, k}}), relaxed)) ok = false;
          if (!ok) continue;
          auto weights = [&](const std::vector<PetscInt>& w, int e) {
            std::vector<double> s(w.begin(), w.end());
            return lagrange(s, target[e]);
          };
          const auto ax = weights(wx, 0), ay = weights(wy, 1), az = weights(wz, 2);
          FaceValue v;
          for (std::size_t c = 0; c < wz.size(); ++c)
            for (std::size_t b = 0; b < wy.size(); ++b)
              for (std::size_t a = 0; a < wx.size(); ++a)
                v.add(value({level, normal, {wx[a], wy[b], wz[c]}}), ax[a] * ay[b] * az[c]);
          return v;
        }
  }
  throw std::logic_error(fmt::format("composite velocity: no interpolation stencil on level {} for the "
                                     "normal-{} velocity at ({:g}, {:g}, {:g})",
                                     level, normal, x[0], x[1], x[2]));
}

std::vector<double> CompositeVelocity::data_values(const VelocityFunction& wall_velocity, double t) const
{
  std::vector<double> values(data_points_.size(), 0.0);
  if (!wall_velocity) return values;
  for (std::size_t i = 0; i < data_points_.size(); ++i)
    values[i] = wall_velocity(data_points_[i].x, t)[data_points_[i].component];
  return values;
}

void CompositeVelocity::laplacian_data(const std::vector<double>& data, Vec out) const
{
  PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArray(out, &a));
  for (std::size_t f = 0; f < laplacian_data_.size(); ++f) {
    double s = 0.0;
    for (const auto& [i, w] : laplacian_data_[f]) s += w * data[static_cast<std::size_t>(i)];
    a[f] = s;
  }
  PETSC_CHECK(VecRestoreArray(out, &a));
}

void CompositeVelocity::cell_velocity(Vec u, const VelocityFunction& wall_velocity, double t,
                                      const std::array<Vec, 3>& out) const
{
  const std::vector<double> all = gather(u);
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(VecGetOwnershipRange(out[0], &begin, &end));
  // The face values first: value() may add wall data points, which data_values() must then cover.
  std::vector<std::array<const FaceValue*, 6>> faces(static_cast<std::size_t>(end - begin));
  operators_->cells().for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& c) {
    for (int d = 0; d < 3; ++d) {
      Index3 upper = c.index;
      ++upper[d];
      faces[static_cast<std::size_t>(n - begin)][2 * d] = &value({c.level, d, c.index});
      faces[static_cast<std::size_t>(n - begin)][2 * d + 1] = &value({c.level, d, upper});
    }
  });
  const std::vector<double> data = data_values(wall_velocity, t);
  for (int d = 0; d < 3; ++d) {
    PetscScalar* a = nullptr;
    PETSC_CHECK(VecGetArray(out[d], &a));
    for (std::size_t i = 0; i < faces.size(); ++i)
      a[i] = 0.5 * (evaluate(*faces[i][2 * d], all, data) + evaluate(*faces[i][2 * d + 1], all, data));
    PETSC_CHECK(VecRestoreArray(out[d], &a));
  }
}

std::vector<double> CompositeVelocity::gather(Vec u) const
{
  std::vector<double> all;
  petsc::with_scattered(gather_, u, gathered_,
                        [&](std::span<const double> a) { all.assign(a.begin(), a.end()); });
  return all;
}

double CompositeVelocity::evaluate(const FaceValue& value, const std::vector<double>& all,
                                   const std::vector<double>& data)
{
  double s = 0.0;
  for (const auto& [i, w] : value.unknowns) s += w * all[static_cast<std::size_t>(i)];
  for (const auto& [i, w] : value.data) s += w * data[static_cast<std::size_t>(i)];
  return s;
}

void CompositeVelocity::evaluate(const FaceValueTable& table, Vec u, std::span<const double> data,
                                 std::span<double> out) const
{
  petsc::with_scattered(gather_, u, gathered_,
                        [&](std::span<const double> all) { table.evaluate(all, data, out); });
}

void CompositeVelocity::convection(Vec u, const std::vector<double>& data, Vec out,
                                   ConvectionScheme scheme) const
{
  std::vector<double>& v = convection_buffer_;
  evaluate(convection_values_, u, data, v);
  const GridHierarchy& h = hierarchy();
  const bool limited = scheme == ConvectionScheme::limited_upwind;
  // The owned faces' own values (the local part of u, in the order of owned_keys_).
  const PetscScalar* own = nullptr;
  PETSC_CHECK(VecGetArrayRead(u, &own));
  PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArray(out, &a));
  for (std::size_t f = 0; f < owned_keys_.size(); ++f) {
    const FaceKey& k = owned_keys_[f];
    const auto& s = convection_stencils_[f];
    const double self = own[f];
    double n = 0.0;
    for (int e = 0; e < 3; ++e) {
      const auto at = [&](int j) { return v[static_cast<std::size_t>(s[8 * e + j])]; };
      // u_e on the momentum cell's +e and -e sides, averaged along d (the carrier), times u_d there: averaged
      // along e (centred) or reconstructed from the upwind side (limited kappa = 1/3, fluid/convection.hpp).
      const double mm = at(0), m = at(1), p = at(2), pp = at(3);
      const double carrier_up = 0.5 * (at(4) + at(5)), carrier_down = 0.5 * (at(6) + at(7));
      double up = 0.5 * (self + p), down = 0.5 * (m + self);
      if (limited) {
        up = carrier_up >= 0.0 ? limited_face_value(m, self, p, pp) : limited_face_value(pp, p, self, m);
        down = carrier_down >= 0.0 ? limited_face_value(mm, m, self, p) : limited_face_value(p, self, m, mm);
      }
      n += (carrier_up * up - carrier_down * down) / h.h(k.level, e);
    }
    a[f] = n;
  }
  PETSC_CHECK(VecRestoreArray(out, &a));
  PETSC_CHECK(VecRestoreArrayRead(u, &own));
}

FaceValueTable::FaceValueTable(std::span<const FaceValue* const> values)
{
  unknown_begin_.reserve(values.size() + 1);
  data_begin_.reserve(values.size() + 1);
  unknown_begin_.push_back(0);
  data_begin_.push_back(0);
  for (const FaceValue* v : values) {
    if (v) {
      for (const auto& [i, w] : v->unknowns) {
        unknown_index_.push_back(i);
        unknown_weight_.push_back(w);
      }
      for (const auto& [i, w] : v->data) {
        data_index_.push_back(i);
        data_weight_.push_back(w);
      }
    }
    unknown_begin_.push_back(unknown_index_.size());
    data_begin_.push_back(data_index_.size());
  }
}

void FaceValueTable::evaluate(std::span<const double> all, std::span<const double> data,
                              std::span<double> out) const
{
  if (out.size() != size()) throw std::logic_error("FaceValueTable: the output does not fit the table");
  for (std::size_t r = 0; r < size(); ++r) {
    double s = 0.0;
    for (std::size_t t = unknown_begin_[r]; t < unknown_begin_[r + 1]; ++t)
      s += unknown_weight_[t] * all[static_cast<std::size_t>(unknown_index_[t])];
    for (std::size_t t = data_begin_[r]; t < data_begin_[r + 1]; ++t)
      s += data_weight_[t] * data[static_cast<std::size_t>(data_index_[t])];
    out[r] = s;
  }
}

} // namespace ibvalve::fluid
