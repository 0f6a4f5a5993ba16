// Reading a package's image.bin and rays.csv, writing hits.csv
// (docs/memory-format.md), for the golden walk's command-line tool and tests.
#pragma once
#include <string>
#include <vector>

#include "walk.h"

namespace rtg {

// Each throws std::runtime_error naming the file (and line) on bad input.
Image read_image(const std::string& path);
std::vector<RayIn> read_rays_csv(const std::string& path);
void write_hits_csv(const std::string& path, const std::vector<HitOut>& hits);
// Shortest decimal that reads back to the same float (Rust's `{}` for f32).
std::string float_text(float x);

}  // namespace rtg
