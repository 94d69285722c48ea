/* curray core: W rays at a time in the lanes of a vector (the CPU packet
 * path, src/render/cpu_packet.c).
 *
 * A translation unit that defines CR_LANES (4: AVX2, 8: AVX-512F) and is
 * compiled for that instruction set gets:
 *   cr_vd, cr_vm    W doubles, and W 64-bit masks (all ones or zero) as the
 *                   comparisons of two cr_vd give them
 *   cr_v_sel, cr_v_abs, cr_v_sqrt, cr_v_bc, cr_v_any, cr_v_bits: lane-wise
 *                   select, fabs, correctly rounded sqrt, broadcast, any
 *                   lane set, the set lanes as bits (lane i: bit i)
 *   the lane-generic part of mino.h (mino_lane.h) over cr_vd, each name
 *   with the suffix _v: cr_mino_v (one ray's coefficients per lane),
 *   cr_mino_rhs_v, cr_mino_monitor_v, cr_dp5_v, cr_dp5_try_v,
 *   cr_dp5_control_v, cr_mino_escaping_v, ...: the very formulas of the
 *   scalar path, lane by lane, in the same order of operations;
 *   cr_v_mino_set: one ray's cr_mino into lane i of a cr_mino_v.
 * The vector extensions are GCC and clang's; nvcc, the WebAssembly build
 * and C++ never see them: for those (and without CR_LANES) this header is
 * empty, and nothing but the packet path includes it.
 */
#ifndef CR_CORE_LANES_H
#define CR_CORE_LANES_H

#if defined(CR_LANES) && defined(__GNUC__) && defined(__x86_64__) && !defined(__CUDACC__) &&    \
    !defined(__EMSCRIPTEN__) && !defined(__cplusplus)

#include <immintrin.h>
#include <stdint.h>

#include "mino.h"

#if CR_LANES == 4
#ifndef __AVX2__
#error "CR_LANES 4 needs a translation unit compiled for AVX2 (-mavx2)"
#endif
typedef double cr_vd __attribute__((vector_size(32)));
typedef int64_t cr_vm __attribute__((vector_size(32)));
static inline cr_vd cr_v_sqrt(cr_vd x)
{
    return _mm256_sqrt_pd(x);
}
static inline unsigned cr_v_bits(cr_vm m)
{
    return (unsigned)_mm256_movemask_pd((__m256d)m);
}
#elif CR_LANES == 8
#ifndef __AVX512F__
#error "CR_LANES 8 needs a translation unit compiled for AVX-512F (-mavx512f)"
#endif
typedef double cr_vd __attribute__((vector_size(64)));
typedef int64_t cr_vm __attribute__((vector_size(64)));
static inline cr_vd cr_v_sqrt(cr_vd x)
{
    return _mm512_sqrt_pd(x);
}
static inline unsigned cr_v_bits(cr_vm m)
{
    return (unsigned)_mm512_test_epi64_mask((__m512i)m, (__m512i)m);
}
#else
#error "CR_LANES must be 4 or 8"
#endif

/* Whether any lane of mask m is set. */
static inline int cr_v_any(cr_vm m)
{
    return cr_v_bits(m) != 0;
}

static inline cr_vd cr_v_sel(cr_vm m, cr_vd a, cr_vd b)
{
    return (cr_vd)(((cr_vm)a & m) | ((cr_vm)b & ~m));
}

static inline cr_vd cr_v_abs(cr_vd x)
{
    return (cr_vd)((cr_vm)x & INT64_MAX);
}

static inline cr_vd cr_v_bc(double x)
{
    cr_vd zero = {0};
    return x - zero; /* x in every lane (x - 0 keeps the sign of -0) */
}

#define CR_L cr_vd
#define CR_LM cr_vm
#define CR_LN(x) x##_v
#define CR_LHD
#define CR_LSEL(m, a, b) cr_v_sel((m), (a), (b))
#define CR_LABS(x) cr_v_abs(x)
#define CR_LSQRT(x) cr_v_sqrt(x)
#define CR_LBC(x) cr_v_bc(x)
#define CR_LANY(m) cr_v_any(m)
#include "mino_lane.h"
#undef CR_L
#undef CR_LM
#undef CR_LN
#undef CR_LHD
#undef CR_LSEL
#undef CR_LABS
#undef CR_LSQRT
#undef CR_LBC
#undef CR_LANY

/* cr_mino and cr_mino_v have the same fields, all of their lane type, in
 * the same order (both are mino_lane.h's struct). */
_Static_assert(sizeof(cr_mino_v) == sizeof(cr_mino) * CR_LANES,
               "cr_mino_v holds CR_LANES cr_mino field by field");

/* Put the coefficients of one ray into lane i of v. */
static inline void cr_v_mino_set(cr_mino_v *v, int i, const cr_mino *c)
{
    const double *s = (const double *)c;
    double *d = (double *)v;
    size_t k;
    for (k = 0; k < sizeof *c / sizeof(double); k++)
        d[k * CR_LANES + (size_t)i] = s[k];
}

#endif /* CR_LANES and a compiler with vector extensions */

#endif
