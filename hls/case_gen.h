// Seeded random case generators for the test benches. Each case belongs to a
// named family (its first token in the .out files). Families and weights:
// docs/kernels.md, "Random vectors".
#pragma once
#include "case_io.h"
#include "rng.h"

namespace rt {

BoxCase random_box_case(Rng& rng);
TriCase random_tri_case(Rng& rng);

}  // namespace rt
