#include "fluid/walled_side_capacitance.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "fluid/fft_stokes.hpp"

namespace ibvalve::fluid {

namespace {

/// The end block of (T + mu I)^-1 for the 1-D pressure operator along z on n cells of size h,
/// T x_i = (-x_{i-1} + 2 x_i - x_{i+1}) / h^2 closed by x_{-1} = -x_0 at a traction end (Dirichlet at
/// the face) or x_{-1} = x_0 at a velocity end (Neumann): entries (0, 0), (0, n-1), (n-1, n-1).
/// Thomas elimination of the two unit right sides; `c` and `d` are work arrays of size n.
std::array<double, 3> end_block(std::ptrdiff_t n, double h, double mu, const std::array<bool, 2>& dirichlet,
                                std::vector<double>& c, std::vector<double>& d)
{
  const double off = -1.0 / (h * h);
  auto diagonal = [&](std::ptrdiff_t i) {
    double v = 2.0 / (h * h) + mu;
    if (i == 0) v += (dirichlet[0] ? 1.0 : -1.0) / (h * h);
    if (i == n - 1) v += (dirichlet[1] ? 1.0 : -1.0) / (h * h);
    return v;
  };
  std::array<double, 3> block{};
  for (int rhs = 0; rhs < 2; ++rhs) {
    // Forward sweep: c_i the modified super-diagonal, d_i the modified right side.
    double denominator = diagonal(0);
    c[0] = off / denominator;
    d[0] = (rhs == 0 ? 1.0 : 0.0) / denominator;
    for (std::ptrdiff_t i = 1; i < n; ++i) {
      denominator = diagonal(i) - off * c[static_cast<std::size_t>(i - 1)];
      c[static_cast<std::size_t>(i)] = off / denominator;
      const double f = (rhs == 1 && i == n - 1) ? 1.0 : 0.0;
      d[static_cast<std::size_t>(i)] = (f - off * d[static_cast<std::size_t>(i - 1)]) / denominator;
    }
    // Back substitution, keeping x_{n-1} and x_0.
    double x = d[static_cast<std::size_t>(n - 1)];
    const double last = x;
    for (std::ptrdiff_t i = n - 2; i >= 0; --i)
      x = d[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(i)] * x;
    if (rhs == 0) {
      block[0] = x;    // (0, 0)
      block[1] = last; // (n-1, 0) = (0, n-1)
    } else {
      block[2] = last; // (n-1, n-1)
    }
  }
  return block;
}

double dot(const std::vector<double>& a, const std::vector<double>& b)
{
  return std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
}

} // namespace

std::unique_ptr<WalledSideCapacitance> WalledSideCapacitance::make(const StaggeredGrid& grid,
                                                                   const BoundaryConditions& bc,
                                                                   const SeparableTransformSolver& poisson)
{
  if (bc.periodic(2)) return nullptr;
  const PetscInt nx = grid.cells(0), ny = grid.cells(1), nz = grid.cells(2);
  std::array<std::vector<double>, 2> walled;
  bool any = false;
  for (int upper = 0; upper < 2; ++upper) {
    const int s = side_index(2, upper);
    if (bc.side(s).kind != SideKind::traction || !bc.side(s).wall) continue;
    std::vector<double> mask(static_cast<std::size_t>(nx * ny), 0.0);
    bool side_walled = false;
    for (PetscInt j = 0; j < ny; ++j)
      for (PetscInt i = 0; i < nx; ++i)
        if (!bc.traction_at(s, grid.face_position(2, i, j, upper ? nz : 0))) {
          mask[static_cast<std::size_t>(j * nx + i)] = 1.0;
          side_walled = true;
        }
    if (side_walled) walled[static_cast<std::size_t>(upper)] = std::move(mask);
    any = any || side_walled;
  }
  if (!any) return nullptr;
  return std::make_unique<WalledSideCapacitance>(grid, poisson, std::move(walled));
}

WalledSideCapacitance::WalledSideCapacitance(const StaggeredGrid& grid,
                                             const SeparableTransformSolver& poisson,
                                             std::array<std::vector<double>, 2> walled)
    : comm_(grid.comm()), nx_(poisson.axis(0).unknowns), ny_(poisson.axis(1).unknowns),
      nz_(poisson.axis(2).unknowns)
{
  const auto plane = static_cast<std::size_t>(nx_ * ny_);
  for (int end = 0; end < 2; ++end) {
    const std::vector<double>& m = walled[static_cast<std::size_t>(end)];
    if (m.empty()) continue;
    if (m.size() != plane) throw std::logic_error("walled-side capacitance: a mask of the wrong size");
    planes_.push_back(end);
    mask_.insert(mask_.end(), m.begin(), m.end());
  }
  walled_count_ = static_cast<std::size_t>(std::count(mask_.begin(), mask_.end(), 1.0));
  const double h = grid.h(2);
  a_ = 2.0 / (h * h);
  // The 1-D operator along z: the pressure axis's ends are Dirichlet (traction) or Neumann (velocity);
  // a walled z side is a traction side.
  const TransformAxis& z = poisson.axis(2);
  std::array<bool, 2> dirichlet{};
  switch (z.forward) {
  case FFTW_RODFT10:
    dirichlet = {true, true};
    break;
  case FFTW_REDFT11:
    dirichlet = {false, true};
    break;
  case FFTW_RODFT11:
    dirichlet = {true, false};
    break;
  default:
    throw std::logic_error("walled-side capacitance: the z axis has no traction end");
  }
  const TransformAxis &x = poisson.axis(0), &y = poisson.axis(1);
  normalisation_ = x.normalisation * y.normalisation;
  g00_.resize(plane);
  g01_.resize(plane);
  g11_.resize(plane);
  std::vector<double> c(static_cast<std::size_t>(nz_)), d(static_cast<std::size_t>(nz_));
  for (std::ptrdiff_t jy = 0; jy < ny_; ++jy)
    for (std::ptrdiff_t jx = 0; jx < nx_; ++jx) {
      const double mu =
          x.eigenvalues[static_cast<std::size_t>(jx)] + y.eigenvalues[static_cast<std::size_t>(jy)];
      const auto block = end_block(nz_, h, mu, dirichlet, c, d);
      const auto m = static_cast<std::size_t>(jy * nx_ + jx);
      g00_[m] = block[0];
      g01_[m] = block[1];
      g11_[m] = block[2];
    }

  const std::size_t n = mask_.size();
  rhs_.resize(static_cast<std::size_t>(poisson.local_size()));
  for (std::vector<double>* v : {&g_, &s_, &r_, &p_, &q_}) v->assign(n, 0.0);
  buffer_ = make_fftw_buffer(n);
  const int dims[2] = {static_cast<int>(ny_), static_cast<int>(nx_)};
  const fftw_r2r_kind forward[2] = {y.forward, x.forward}, backward[2] = {y.backward, x.backward};
  const int howmany = static_cast<int>(planes_.size()), dist = static_cast<int>(plane);
  double* data = buffer_.get();
  forward_.reset(fftw_plan_many_r2r(2, dims, howmany, data, nullptr, 1, dist, data, nullptr, 1, dist, forward,
                                    fftw_planner_flags()));
  backward_.reset(fftw_plan_many_r2r(2, dims, howmany, data, nullptr, 1, dist, data, nullptr, 1, dist,
                                     backward, fftw_planner_flags()));
  if (!forward_ || !backward_)
    throw std::runtime_error("walled-side capacitance: FFTW could not plan the plane transforms");
}

void WalledSideCapacitance::apply_plane_green(const std::vector<double>& v, std::vector<double>& out)
{
  std::copy(v.begin(), v.end(), buffer_.get());
  fftw_execute(forward_.get());
  const auto plane = static_cast<std::size_t>(nx_ * ny_);
  const double scale = 1.0 / normalisation_;
  if (planes_.size() == 2) {
    for (std::size_t m = 0; m < plane; ++m) {
      const double b0 = buffer_[m], b1 = buffer_[plane + m];
      buffer_[m] = (g00_[m] * b0 + g01_[m] * b1) * scale;
      buffer_[plane + m] = (g01_[m] * b0 + g11_[m] * b1) * scale;
    }
  } else {
    const std::vector<double>& g = planes_[0] == 0 ? g00_ : g11_;
    for (std::size_t m = 0; m < plane; ++m) buffer_[m] *= g[m] * scale;
  }
  fftw_execute(backward_.get());
  for (std::size_t m = 0; m < out.size(); ++m) out[m] = mask_[m] * buffer_[m];
}

void WalledSideCapacitance::apply_capacitance(const std::vector<double>& v, std::vector<double>& out)
{
  apply_plane_green(v, out);
  for (std::size_t m = 0; m < out.size(); ++m) out[m] = v[m] / a_ - out[m];
}

void WalledSideCapacitance::solve(SeparableTransformSolver& poisson)
{
  double* data = poisson.data();
  const auto local = static_cast<std::size_t>(poisson.local_size());
  std::copy(data, data + local, rhs_.begin());
  poisson.solve(0.0, 1.0); // phi0 = K0^-1 r

  // g = U^T phi0: the owning ranks' planes, summed onto every rank.
  const auto plane = static_cast<std::size_t>(nx_ * ny_);
  std::fill(g_.begin(), g_.end(), 0.0);
  for (std::size_t p = 0; p < planes_.size(); ++p)
    if (const double* slab = slab_plane(poisson, p))
      for (std::size_t m = 0; m < plane; ++m) g_[p * plane + m] = mask_[p * plane + m] * slab[m];
  MPI_Allreduce(MPI_IN_PLACE, g_.data(), static_cast<int>(g_.size()), MPI_DOUBLE, MPI_SUM, comm_);

  // C s = g by conjugate gradients (C symmetric positive definite), to round-off: the solve is meant to
  // be exact, so FGMRES around it sees K^-1.
  std::fill(s_.begin(), s_.end(), 0.0);
  r_ = g_;
  p_ = r_;
  double rr = dot(r_, r_);
  const double stop = 1e-26 * rr; // relative residual 1e-13
  last_iterations_ = 0;
  const int max_iterations = static_cast<int>(std::min<std::size_t>(walled_count_ + 1, 2000));
  while (rr > stop && rr > 0.0 && last_iterations_ < max_iterations) {
    apply_capacitance(p_, q_);
    const double alpha = rr / dot(p_, q_);
    for (std::size_t m = 0; m < s_.size(); ++m) {
      s_[m] += alpha * p_[m];
      r_[m] -= alpha * q_[m];
    }
    const double rr_new = dot(r_, r_);
    const double beta = rr_new / rr;
    rr = rr_new;
    for (std::size_t m = 0; m < p_.size(); ++m) p_[m] = r_[m] + beta * p_[m];
    ++last_iterations_;
  }

  // phi = K0^-1 (r + U s).
  std::copy(rhs_.begin(), rhs_.end(), data);
  for (std::size_t p = 0; p < planes_.size(); ++p)
    if (double* slab = slab_plane(poisson, p))
      for (std::size_t m = 0; m < plane; ++m) slab[m] += s_[p * plane + m];
  poisson.solve(0.0, 1.0);
}

double* WalledSideCapacitance::slab_plane(SeparableTransformSolver& poisson, std::size_t p) const
{
  const std::ptrdiff_t k = planes_[p] == 0 ? 0 : nz_ - 1;
  if (k < poisson.z_begin() || k >= poisson.z_begin() + poisson.z_count()) return nullptr;
  return poisson.data() +
         static_cast<std::size_t>(k - poisson.z_begin()) * static_cast<std::size_t>(nx_ * ny_);
}

} // namespace ibvalve::fluid
