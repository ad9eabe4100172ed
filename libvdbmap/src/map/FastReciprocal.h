// SPDX-License-Identifier: Apache-2.0
#pragma once

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace vdbmap::detail {

/// 1 / x for a normal, positive float x, to 1.5 * 2^-12 relative: the SSE estimate alone. The
/// voxel kernel's distance falloff, a weight, uses it (a weight 4e-4 off moves the average by
/// less than that share of the difference between two samples).
inline float reciprocalEstimate(float x) {
#if defined(__SSE__)
    return _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x)));
#else
    return 1.0f / x;
#endif
}

/// 1 / x for a normal, positive float x, to about 2 ulp: the SSE estimate (12 bits) refined by
/// one Newton step, r' = r (2 - x r). Pipelined multiplies instead of a division (divss: ~10
/// cycles of latency on the voxel loop's critical path). The voxel kernel's running average
/// uses it; the result is quantized to 16 bits afterwards, far coarser than its error.
inline float fastReciprocal(float x) {
#if defined(__SSE__)
    const float r = _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x)));
    return r * (2.0f - x * r);
#else
    return 1.0f / x;
#endif
}

}  // namespace vdbmap::detail
