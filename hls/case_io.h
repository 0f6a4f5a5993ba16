// Reading the shared hard-case files (testdata/kernels/*.txt) and writing the
// kernel output vectors (hls/build/vectors/*.out). Formats: docs/kernels.md.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rt {

struct BoxCase {
  std::string family;
  float o[3], d[3], tmin, tmax, bmin[3], bmax[3];
};

struct TriCase {
  std::string family;
  float o[3], d[3], tmin, tmax, p0[3], p1[3], p2[3];
};

// Both throw std::runtime_error naming the file, the line and the bad token.
std::vector<BoxCase> read_box_cases(const std::string& path);
std::vector<TriCase> read_tri_cases(const std::string& path);

// Text form of a case's inputs, as in the hard-case files: 8 hex digits per
// float, NaN written canonically (7fc00000).
std::string hex(float x);
std::string box_inputs_line(const BoxCase& c);
std::string tri_inputs_line(const TriCase& c);

// Opens a file for writing or throws naming it.
FILE* open_or_throw(const std::string& path, const char* mode);

}  // namespace rt
