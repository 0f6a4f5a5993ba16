// rays.csv of a scene package (header `ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow`,
// floats as nori-bridge writes them: shortest round-trip text, inf, -inf, NaN)
// into ray records. strtof rounds correctly, so each float is the one the
// Scala reader (ScenePackage.readRays) gets.
#pragma once
#include <string>
#include <vector>

#include "rtaccel.h"

namespace rtaccel::sim {

// Reads at most `limit` rays (0: all). On failure returns false with a message
// naming the file, line and value. Ray numbers must be 0, 1, 2, ... in order
// (the hardware numbers ray i as i).
bool readRaysCsv(const std::string& path, size_t limit, std::vector<rtaccel_ray>& out, std::string& err);

}  // namespace rtaccel::sim
