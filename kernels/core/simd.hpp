// A fixed-width pack of doubles, one lane per element of a batch, so that batched element kernels
// are written once as scalar-looking code and compiled to packed arithmetic: every operator is a
// loop over the lanes that the compiler vectorises after inlining (AVX2/AVX-512 with
// -march=native). On a GPU one thread owns one element, so the pack degenerates to a plain double
// (SimdValue<1> = Real) and the same source compiles there.
#pragma once

#include <type_traits>

#include "types.hpp"

namespace biofsi {

// Full unrolling of the short fixed-trip loops of the batched kernels: their bounds and the stored
// pattern are compile-time constants, so unrolled they leave straight-line packed arithmetic with
// the operands in registers instead of a loop that tests the pattern at every entry.
// nvcc's device pass takes "unroll"; its host pass knows neither that nor GCC's form, and the
// host side of a CUDA build does not run these kernels, so it gets none.
#if defined(__CUDA_ARCH__) || defined(__clang__)
#define BIOFSI_UNROLL _Pragma("unroll")
#elif defined(__CUDACC__)
#define BIOFSI_UNROLL
#elif defined(__GNUC__)
#define BIOFSI_UNROLL _Pragma("GCC unroll 64")
#else
#define BIOFSI_UNROLL
#endif

// Elements per batch in the execution space: 8 doubles fill an AVX-512 register (two AVX2 ones);
// one on CUDA, where lanes are threads.
#if defined(KOKKOS_ENABLE_CUDA)
constexpr int simd_width = 1;
#else
constexpr int simd_width = 8;
#endif

template <int W>
struct Pack {
  Real v[W];

  Pack() = default;
  KOKKOS_INLINE_FUNCTION Pack(Real s) {  // NOLINT: broadcast, as for a scalar
    for (int i = 0; i < W; ++i) v[i] = s;
  }
  KOKKOS_INLINE_FUNCTION Pack& operator+=(const Pack& o) {
    for (int i = 0; i < W; ++i) v[i] += o.v[i];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Pack& operator-=(const Pack& o) {
    for (int i = 0; i < W; ++i) v[i] -= o.v[i];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Pack& operator*=(const Pack& o) {
    for (int i = 0; i < W; ++i) v[i] *= o.v[i];
    return *this;
  }
};

template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator+(Pack<W> a, const Pack<W>& b) {
  return a += b;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator-(Pack<W> a, const Pack<W>& b) {
  return a -= b;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator*(Pack<W> a, const Pack<W>& b) {
  return a *= b;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator*(Real s, Pack<W> a) {
  for (int i = 0; i < W; ++i) a.v[i] *= s;
  return a;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator*(Pack<W> a, Real s) {
  return s * a;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator/(Pack<W> a, Real s) {
  for (int i = 0; i < W; ++i) a.v[i] /= s;
  return a;
}

// Mixed with a scalar (broadcast): a template's deduction does not convert, so each is spelled out.
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator+(Real s, const Pack<W>& a) {
  return Pack<W>(s) += a;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator+(Pack<W> a, Real s) {
  return a += Pack<W>(s);
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator-(Real s, const Pack<W>& a) {
  return Pack<W>(s) -= a;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator-(Pack<W> a, Real s) {
  return a -= Pack<W>(s);
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator/(Pack<W> a, const Pack<W>& b) {
  for (int i = 0; i < W; ++i) a.v[i] /= b.v[i];
  return a;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> operator/(Real s, const Pack<W>& b) {
  Pack<W> a;
  for (int i = 0; i < W; ++i) a.v[i] = s / b.v[i];
  return a;
}
template <int W>
KOKKOS_INLINE_FUNCTION Pack<W> abs_value(Pack<W> a) {
  for (int i = 0; i < W; ++i) a.v[i] = a.v[i] < 0 ? -a.v[i] : a.v[i];
  return a;
}
KOKKOS_INLINE_FUNCTION Real abs_value(Real a) { return math::fabs(a); }

// The value type of a batch of W elements.
template <int W>
using SimdValue = std::conditional_t<W == 1, Real, Pack<W>>;

// Lane access that works for both a pack and a plain double.
template <int W>
KOKKOS_INLINE_FUNCTION Real& lane(Pack<W>& p, int i) {
  return p.v[i];
}
template <int W>
KOKKOS_INLINE_FUNCTION Real lane(const Pack<W>& p, int i) {
  return p.v[i];
}
KOKKOS_INLINE_FUNCTION Real& lane(Real& p, int) { return p; }
KOKKOS_INLINE_FUNCTION Real lane(const Real& p, int) { return p; }

}  // namespace biofsi
