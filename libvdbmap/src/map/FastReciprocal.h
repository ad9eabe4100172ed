// SPDX-License-Identifier: Apache-2.0
#pragma once

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace vdbmap::detail {

/// 1 / x for a normal, positive float x, to about 2 ulp: the SSE estimate (12 bits) refined by
/// one Newton step, r' = r (2 - x r). Pipelined multiplies instead of a division (divss: ~10
/// cycles of latency on the voxel loop's critical path). The voxel kernel uses it for its two
/// divisions per update (the distance falloff and the running average); the result is
/// quantized to 16 bits afterwards, far coarser than the estimate's error.
inline float fastReciprocal(float x) {
#if defined(__SSE__)
    const float r = _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x)));
    return r * (2.0f - x * r);
#else
    return 1.0f / x;
#endif
}

}  // namespace vdbmap::detail
