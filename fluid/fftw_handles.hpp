#pragma once
// Owned FFTW objects: a plan and FFTW-aligned real and complex buffers that free themselves, so a constructor
// that fails after allocating (FFTW returning no plan) throws without leaking or freeing twice.
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>

#include <fftw3.h>

namespace ibvalve::fluid {

struct FftwPlanDestroy {
  void operator()(fftw_plan plan) const { fftw_destroy_plan(plan); }
};
using FftwPlan = std::unique_ptr<std::remove_pointer_t<fftw_plan>, FftwPlanDestroy>;

struct FftwFree {
  void operator()(double* data) const { fftw_free(data); }
};
using FftwBuffer = std::unique_ptr<double[], FftwFree>;

struct FftwComplexFree {
  void operator()(fftw_complex* data) const { fftw_free(data); }
};
using FftwComplexBuffer = std::unique_ptr<fftw_complex[], FftwComplexFree>;

/// `count` complex values aligned for FFTW's SIMD transforms; std::bad_alloc when there is no memory.
inline FftwComplexBuffer make_fftw_complex_buffer(std::size_t count)
{
  FftwComplexBuffer buffer(fftw_alloc_complex(count > 0 ? count : 1));
  if (!buffer) throw std::bad_alloc();
  return buffer;
}

/// `count` doubles aligned for FFTW's SIMD transforms; std::bad_alloc when there is no memory.
inline FftwBuffer make_fftw_buffer(std::size_t count)
{
  FftwBuffer buffer(fftw_alloc_real(count > 0 ? count : 1));
  if (!buffer) throw std::bad_alloc();
  return buffer;
}

} // namespace ibvalve::fluid
