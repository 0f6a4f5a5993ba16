// HLS kernel: ray/box slab test. One pipelined call per (ray, box) pair.
// Every float operation below rounds once (RNE); build with
// -ffp-contract=off so no multiply-add is fused.
#include "bbox_intersect.h"
#include "fp32.h"
#include "ray_setup.h"

namespace rt {

void bbox_intersect(const float o[3], const float d[3], const float rcp[3],
                    float tmin, float tmax,
                    const float bmin[3], const float bmax[3], BoxResult* out) {
#pragma HLS PIPELINE II=1
#pragma HLS INTERFACE ap_ctrl_none port=return
#pragma HLS ARRAY_PARTITION variable=o complete
#pragma HLS ARRAY_PARTITION variable=d complete
#pragma HLS ARRAY_PARTITION variable=rcp complete
#pragma HLS ARRAY_PARTITION variable=bmin complete
#pragma HLS ARRAY_PARTITION variable=bmax complete
  float near = -kInf;
  float far = kInf;
  bool inside_flat = true;  // zero-direction axes: origin inside the slab
  bool box_valid = true;    // bmin <= bmax on every axis (false for NaN/empty)
  for (int i = 0; i < 3; ++i) {
#pragma HLS UNROLL
    // B1..B4: plane distances. NaN only as 0 * inf: the origin lies exactly on
    // the plane (difference +-0) and |d| is so small that 1/d overflowed.
    const float t_min_plane = (bmin[i] - o[i]) * rcp[i];
    const float t_max_plane = (bmax[i] - o[i]) * rcp[i];
    // B5: order by the sign of d instead of a compare-and-swap. For a valid
    // box and non-NaN distances this equals the ordered pair (monotone
    // rounding keeps t_min_plane <= t_max_plane when rcp > 0), and it keeps a
    // NaN on its own side, where max_num/min_num below ignore it.
    const bool neg = sign_bit(d[i]);
    const float lo = neg ? t_max_plane : t_min_plane;
    const float hi = neg ? t_min_plane : t_max_plane;
    const bool flat = is_zero(d[i]);
    // B6: a zero component (either sign) tests the origin against the slab.
    inside_flat = inside_flat && (flat ? (o[i] >= bmin[i] && o[i] <= bmax[i]) : true);
    box_valid = box_valid && (bmin[i] <= bmax[i]);
    // B7: fold; NaN loses so a NaN distance never shrinks [near, far].
    near = max_num(near, flat ? -kInf : lo);
    far = min_num(far, flat ? kInf : hi);
  }
  const bool err = ray_error(o, d, tmin, tmax);
  // B8: closed intervals, all four comparisons IEEE (false on NaN; -0 == +0).
  out->hit = !err && box_valid && inside_flat && near <= far && tmin <= far && near <= tmax;
  out->err = err;
  out->near = near;
}

}  // namespace rt
