// Groups of the "shared_*" hard cases of tri_hard.txt: consecutive lines with
// the same family and the same ray are the triangles around one edge or one
// vertex, and the ray must hit at least one of them (docs/kernels.md §7).
#pragma once
#include <string>
#include <vector>

#include "case_io.h"
#include "fp32.h"

namespace rt {

struct CaseGroup {
  std::string family;
  size_t begin, end;  // [begin, end) indices into the case list
};

inline bool same_group(const TriCase& a, const TriCase& b) {
  for (int i = 0; i < 3; ++i)
    if (bits(a.o[i]) != bits(b.o[i]) || bits(a.d[i]) != bits(b.d[i])) return false;
  return a.family == b.family;
}

// The groups among the first n cases.
inline std::vector<CaseGroup> shared_groups(const std::vector<TriCase>& cases, size_t n) {
  std::vector<CaseGroup> groups;
  for (size_t k = 0; k < n; ++k) {
    if (cases[k].family.rfind("shared_", 0) != 0) continue;
    if (!groups.empty() && groups.back().end == k && same_group(cases[groups.back().begin], cases[k]))
      groups.back().end = k + 1;
    else
      groups.push_back({cases[k].family, k, k + 1});
  }
  return groups;
}

}  // namespace rt
