// Double-precision references for the test benches (not kernels).
#pragma once
#include "case_io.h"

namespace rt {

// Box reference: the slab test evaluated in f64 on the FP32 inputs, with
// t = (b - o) / d (no reciprocal; an origin on a plane gives t = 0 exactly).
// `robust` means FP32 cannot miss: the f64 interval still overlaps after
// every plane distance is moved by its FP32 error bound (see box_error_bound).
struct BoxRef {
  bool hit;
  bool robust;          // hit, and hit with margin > the FP32 error bound
  const char* fragile;  // why a hit is not robust: "margin", "rcp_overflow", "diff_overflow"
};
BoxRef box_ref_f64(const BoxCase& c);

// Bound on |t_fp32 - t| for t = (b - o) * rcp, three RNE roundings
// (sub, 1/d, mul): gamma(3) |t| + underflow term; see docs/kernels.md.
double box_error_bound(double t, double diff);

// Triangle reference: Moller-Trumbore in f64 on the FP32 inputs, no epsilon
// (det == 0 is the only parallel case), inclusive bounds.
bool tri_ref_f64(const TriCase& c);

}  // namespace rt
