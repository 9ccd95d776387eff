// The line solves of a field step and their factorisation (Thomas elimination and back
// substitution with a factorisation shared by an axis's lines; Sherman–Morrison's correction on a
// periodic axis), in portable loops and, where the processor has it, AVX2 copies of them.
//
// The y and z lines are solved many at once, a row of contiguous values at a time (the inner loop
// vectorises). The x lines, whose values are contiguous, are solved kXLinesTogether at a time:
// four to an AVX2 register (blocks of 4 × 4 values transposed in registers), else as scalar
// recurrences the processor overlaps, each line's running value in a register.
#include "fields/line_solves.h"

#include <vector>

// GCC on x86-64: AVX2 copies of the line solves, chosen at run time (as the normals' loop in
// src/common/random.cpp). The avx2 target has no fused multiply-add, so no copy fuses a multiply
// and an add, and every copy gives the portable one's bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MOREAU_FIELDS_X86_COPIES 1
#include <immintrin.h>
#else
#define MOREAU_FIELDS_X86_COPIES 0
#endif

namespace moreau::fields {
namespace {

constexpr int kVectorLines = internal::kXLinesTogether;

#if MOREAU_FIELDS_X86_COPIES
// Whether this processor runs the AVX2 copies (asked once).
bool HasAvx2() {
  static const bool avx2 = random_internal::Supports(random_internal::InstructionSet::kAvx2);
  return avx2;
}
#endif

// Factors the tridiagonal matrix `diagonal` (n entries), −off above and below it, in place into
// the line solve's pivots and upper coefficients.
void Factor(const std::vector<double>& diagonal, double off, internal::LineSolve* f) {
  const std::size_t n = diagonal.size();
  f->off = off;
  f->inverse_pivot.resize(n);
  f->upper.assign(n, 0.0);
  double previous_upper = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double pivot = diagonal[i] + off * previous_upper;
    f->inverse_pivot[i] = 1.0 / pivot;
    previous_upper = i + 1 < n ? -off / pivot : 0.0;
    f->upper[i] = previous_upper;
  }
}

// `width` lines side by side: line q's value i at c[q + i·stride], n values each.
[[gnu::always_inline]] inline void StridedLines(const internal::LineSolve& f, double* c,
                                                std::int64_t n, std::int64_t stride,
                                                std::int64_t width) {
  double* first = c;
  double* last = c + (n - 1) * stride;
  for (std::int64_t q = 0; q < width; ++q) {
    first[q] += f.lower_face;
    last[q] += f.upper_face;
    first[q] *= f.inverse_pivot[0];
  }
  for (std::int64_t i = 1; i < n; ++i) {
    double* row = c + i * stride;
    const double* before = row - stride;
    const double inverse = f.inverse_pivot[i];
    for (std::int64_t q = 0; q < width; ++q) row[q] = (row[q] + f.off * before[q]) * inverse;
  }
  for (std::int64_t i = n - 2; i >= 0; --i) {
    double* row = c + i * stride;
    const double* after = row + stride;
    const double upper = f.upper[i];
    for (std::int64_t q = 0; q < width; ++q) row[q] -= upper * after[q];
  }
  if (f.periodic_z.empty()) return;
  std::vector<double> y(static_cast<std::size_t>(width));
  for (std::int64_t q = 0; q < width; ++q) {
    y[q] = (first[q] + f.periodic_corner * last[q]) * f.periodic_scale;
  }
  for (std::int64_t i = 0; i < n; ++i) {
    double* row = c + i * stride;
    const double z = f.periodic_z[i];
    for (std::int64_t q = 0; q < width; ++q) row[q] -= y[q] * z;
  }
}

#if MOREAU_FIELDS_X86_COPIES
// The same loops four lines to an instruction (no fused multiply-add: the same bits).
__attribute__((target("avx2"))) void StridedLinesAvx2(const internal::LineSolve& f, double* c,
                                                      std::int64_t n, std::int64_t stride,
                                                      std::int64_t width) {
  StridedLines(f, c, n, stride, width);
}
#endif

// The cyclic correction of `count` contiguous x lines of n values on a periodic axis.
void PeriodicXLines(const internal::LineSolve& f, double* c, std::int64_t n, int count) {
  if (f.periodic_z.empty()) return;
  for (int k = 0; k < count; ++k) {
    double* line = c + k * n;
    const double y = (line[0] + f.periodic_corner * line[n - 1]) * f.periodic_scale;
    for (std::int64_t i = 0; i < n; ++i) line[i] -= y * f.periodic_z[i];
  }
}

// `Count` contiguous x lines of n values from c, solved together with their recurrences
// interleaved (the processor overlaps them; each line's running value stays in a register): the
// same operations per line as SolveStridedLines.
template <int Count>
void SolveXLineGroup(const internal::LineSolve& f, double* c, std::int64_t n) {
  double* line[Count];
  double carry[Count];
  for (int k = 0; k < Count; ++k) {
    line[k] = c + k * n;
    line[k][0] += f.lower_face;
    line[k][n - 1] += f.upper_face;
    carry[k] = line[k][0] * f.inverse_pivot[0];
    line[k][0] = carry[k];
  }
  for (std::int64_t i = 1; i < n; ++i) {
    const double inverse = f.inverse_pivot[i];
    for (int k = 0; k < Count; ++k) {
      carry[k] = (line[k][i] + f.off * carry[k]) * inverse;
      line[k][i] = carry[k];
    }
  }
  for (std::int64_t i = n - 2; i >= 0; --i) {
    const double upper = f.upper[i];
    for (int k = 0; k < Count; ++k) {
      carry[k] = line[k][i] - upper * carry[k];
      line[k][i] = carry[k];
    }
  }
  PeriodicXLines(f, c, n, Count);
}

#if MOREAU_FIELDS_X86_COPIES
// Rows r0…r3 of a 4 × 4 block of doubles, as its columns in o[0…3].
__attribute__((target("avx2"), always_inline)) inline void Transpose4(__m256d r0, __m256d r1,
                                                                      __m256d r2, __m256d r3,
                                                                      __m256d* o) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);
  o[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  o[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  o[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  o[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

constexpr int kVectorGroups = kVectorLines / 4;

// Elimination of the four values i…i+3 of kVectorLines lines: read from c, transposed, kept in
// `scratch` (value i of line 4g + l at scratch[(i kVectorGroups + g) 4 + l]). On the first block
// the first value has no predecessor.
template <bool kFirst>
__attribute__((target("avx2"), always_inline)) inline void EliminateBlock(
    const double* c, std::int64_t n, std::int64_t i, const double* inverse, __m256d off,
    __m256d* carry, double* scratch) {
#pragma GCC unroll 4
  for (int g = 0; g < kVectorGroups; ++g) {
    const double* b = c + 4 * g * n + i;
    __m256d v[4];
    Transpose4(_mm256_loadu_pd(b), _mm256_loadu_pd(b + n), _mm256_loadu_pd(b + 2 * n),
               _mm256_loadu_pd(b + 3 * n), v);
    double* out = scratch + (i * kVectorGroups + g) * 4;
    if constexpr (kFirst) {
      carry[g] = _mm256_mul_pd(v[0], _mm256_broadcast_sd(inverse));
    } else {
      carry[g] = _mm256_mul_pd(_mm256_add_pd(v[0], _mm256_mul_pd(off, carry[g])),
                               _mm256_broadcast_sd(inverse + i));
    }
    _mm256_storeu_pd(out, carry[g]);
#pragma GCC unroll 3
    for (int j = 1; j < 4; ++j) {
      carry[g] = _mm256_mul_pd(_mm256_add_pd(v[j], _mm256_mul_pd(off, carry[g])),
                               _mm256_broadcast_sd(inverse + i + j));
      _mm256_storeu_pd(out + j * 4 * kVectorGroups, carry[g]);
    }
  }
}

// Back substitution of the values i+3…i of kVectorLines lines from `scratch`, transposed back
// into c. On the last block (n a multiple of four) the last value is the eliminated one.
template <bool kLast>
__attribute__((target("avx2"), always_inline)) inline void SubstituteBlock(
    double* c, std::int64_t n, std::int64_t i, const double* upper, __m256d* carry,
    const double* scratch) {
#pragma GCC unroll 4
  for (int g = 0; g < kVectorGroups; ++g) {
    const double* in = scratch + (i * kVectorGroups + g) * 4;
    __m256d v[4];
    if constexpr (kLast) {
      carry[g] = _mm256_loadu_pd(in + 3 * 4 * kVectorGroups);
    } else {
      carry[g] = _mm256_sub_pd(_mm256_loadu_pd(in + 3 * 4 * kVectorGroups),
                               _mm256_mul_pd(_mm256_broadcast_sd(upper + i + 3), carry[g]));
    }
    v[3] = carry[g];
#pragma GCC unroll 3
    for (int j = 2; j >= 0; --j) {
      carry[g] = _mm256_sub_pd(_mm256_loadu_pd(in + j * 4 * kVectorGroups),
                               _mm256_mul_pd(_mm256_broadcast_sd(upper + i + j), carry[g]));
      v[j] = carry[g];
    }
    __m256d rows[4];
    Transpose4(v[0], v[1], v[2], v[3], rows);
    double* b = c + 4 * g * n + i;
    _mm256_storeu_pd(b, rows[0]);
    _mm256_storeu_pd(b + n, rows[1]);
    _mm256_storeu_pd(b + 2 * n, rows[2]);
    _mm256_storeu_pd(b + 3 * n, rows[3]);
  }
}

// kVectorLines contiguous x lines of n ≥ 4 values from c, four lines to an AVX2 register: the
// same operations per line as SolveXLineGroup, so the same bits. Blocks of 4 × 4 values are
// transposed in registers on the way in, and the eliminated values kept transposed in `scratch`
// (n kVectorLines doubles) until the back substitution transposes them back. The registers'
// recurrences are independent, which hides their latency; the next group's lines are prefetched
// while these are eliminated.
__attribute__((target("avx2"))) void SolveXLinesAvx2(const internal::LineSolve& f, double* c,
                                                     std::int64_t n, double* scratch) {
  for (int k = 0; k < kVectorLines; ++k) {
    c[k * n] += f.lower_face;
    c[k * n + n - 1] += f.upper_face;
  }
  const __m256d off = _mm256_set1_pd(f.off);
  const double* inverse = f.inverse_pivot.data();
  const double* upper = f.upper.data();
  const std::int64_t whole = n / 4 * 4;
  // The next group's 8 kVectorLines n bytes: 2 kVectorGroups cache lines per block of four. The
  // addresses may lie past the grid's end (a prefetch never faults), so they are computed as
  // integers.
  const std::uintptr_t next = reinterpret_cast<std::uintptr_t>(c + (kVectorLines - 1) * n) +
                              static_cast<std::uintptr_t>(n) * sizeof(double);
  const auto prefetch = [next](std::int64_t i) {
    for (int q = 0; q < 2 * kVectorGroups; ++q) {
      __builtin_prefetch(reinterpret_cast<const void*>(
          next + static_cast<std::uintptr_t>(i * kVectorLines * 8 + q * 64)));
    }
  };
  __m256d carry[kVectorGroups];
  prefetch(0);
  EliminateBlock<true>(c, n, 0, inverse, off, carry, scratch);
  for (std::int64_t i = 4; i < whole; i += 4) {
    prefetch(i);
    EliminateBlock<false>(c, n, i, inverse, off, carry, scratch);
  }
  double lanes[4];
  for (std::int64_t i = whole; i < n; ++i) {  // the last n mod 4 values, a value at a time
    for (int g = 0; g < kVectorGroups; ++g) {
      const double* b = c + 4 * g * n + i;
      const __m256d v = _mm256_set_pd(b[3 * n], b[2 * n], b[n], b[0]);
      carry[g] = _mm256_mul_pd(_mm256_add_pd(v, _mm256_mul_pd(off, carry[g])),
                               _mm256_broadcast_sd(inverse + i));
      _mm256_storeu_pd(scratch + (i * kVectorGroups + g) * 4, carry[g]);
    }
  }
  for (std::int64_t i = n - 1; i >= whole; --i) {
    for (int g = 0; g < kVectorGroups; ++g) {
      const __m256d eliminated = _mm256_loadu_pd(scratch + (i * kVectorGroups + g) * 4);
      carry[g] =
          i == n - 1
              ? eliminated
              : _mm256_sub_pd(eliminated, _mm256_mul_pd(_mm256_broadcast_sd(upper + i), carry[g]));
      _mm256_storeu_pd(lanes, carry[g]);
      for (int l = 0; l < 4; ++l) c[(4 * g + l) * n + i] = lanes[l];
    }
  }
  std::int64_t i = whole - 4;
  if (whole == n) {
    SubstituteBlock<true>(c, n, i, upper, carry, scratch);
    i -= 4;
  }
  for (; i >= 0; i -= 4) SubstituteBlock<false>(c, n, i, upper, carry, scratch);
  PeriodicXLines(f, c, n, kVectorLines);
}
#endif

}  // namespace

void internal::SolveStridedLines(const internal::LineSolve& f, double* c, std::int64_t n,
                                 std::int64_t stride, std::int64_t width) {
#if MOREAU_FIELDS_X86_COPIES
  if (HasAvx2()) {
    StridedLinesAvx2(f, c, n, stride, width);
    return;
  }
#endif
  StridedLines(f, c, n, stride, width);
}

// The line solve of an axis of n voxels: diagonal 1 + Δt λ/k + 2r, r = D Δt / h², changed on the
// face rows (zero flux: the ghost mirrors the voxel, −r; fixed: the ghost is 2 c_b − c, +r and
// 2 r c_b on the right-hand side), or cyclic on a periodic axis.
internal::LineSolve internal::MakeLineSolve(int n, double r, double decay_part,
                                            const FaceBoundary& lower, const FaceBoundary& upper) {
  internal::LineSolve f;
  const double base = 1.0 + decay_part + 2.0 * r;
  std::vector<double> diagonal(static_cast<std::size_t>(n), base);
  if (lower.kind == BoundaryKind::kPeriodic) {
    if (n <= 2) {  // the neighbours on both sides are the same voxel (n = 2) or the voxel itself
      diagonal.assign(static_cast<std::size_t>(n), n == 1 ? 1.0 + decay_part : base);
      Factor(diagonal, n == 1 ? 0.0 : 2.0 * r, &f);
      return f;
    }
    // Sherman–Morrison: A = T + u vᵀ, u = (γ, 0, …, −r), v = (1, 0, …, −r/γ), γ = −base.
    const double gamma = -base;
    diagonal.front() = base - gamma;
    diagonal.back() = base - r * r / gamma;
    Factor(diagonal, r, &f);
    std::vector<double> z(static_cast<std::size_t>(n), 0.0);
    z.front() = gamma;
    z.back() = -r;
    internal::SolveStridedLines(f, z.data(), n, 1, 1);
    f.periodic_corner = -r / gamma;
    f.periodic_scale = 1.0 / (1.0 + z.front() + f.periodic_corner * z.back());
    f.periodic_z = std::move(z);
    return f;
  }
  const auto face = [&](const FaceBoundary& b, double* row, double* rhs) {
    *row += b.kind == BoundaryKind::kFixed ? r : -r;
    *rhs = b.kind == BoundaryKind::kFixed ? 2.0 * r * b.value : 0.0;
  };
  double lower_face = 0.0;
  double upper_face = 0.0;
  face(lower, &diagonal.front(), &lower_face);
  face(upper, &diagonal.back(), &upper_face);
  Factor(diagonal, r, &f);
  f.lower_face = lower_face;
  f.upper_face = upper_face;
  return f;
}

void internal::SolveXLinesOn(random_internal::InstructionSet set, const LineSolve& f, double* c,
                             std::int64_t n, int count) {
  static_assert(kXLinesTogether == kVectorLines);
#if MOREAU_FIELDS_X86_COPIES
  if (set != random_internal::InstructionSet::kPortable && HasAvx2() && count == kVectorLines &&
      n >= 4) {
    thread_local std::vector<double> scratch;
    if (scratch.size() < static_cast<std::size_t>(n * kVectorLines)) {
      scratch.resize(static_cast<std::size_t>(n * kVectorLines));
    }
    SolveXLinesAvx2(f, c, n, scratch.data());
    return;
  }
#else
  (void)set;
#endif
  // By 8, then 4, 2 and 1.
  for (; count >= 8; count -= 8, c += 8 * n) SolveXLineGroup<8>(f, c, n);
  if (count & 4) SolveXLineGroup<4>(f, c + (count & 3) * n, n);
  if (count & 2) SolveXLineGroup<2>(f, c + (count & 1) * n, n);
  if (count & 1) SolveXLineGroup<1>(f, c, n);
}

}  // namespace moreau::fields
