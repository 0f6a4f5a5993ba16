#include "rays_csv.hpp"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rtaccel::sim {

bool readRaysCsv(const std::string& path, size_t limit, std::vector<rtaccel_ray>& out, std::string& err) {
  std::ifstream in(path);
  if (!in) { err = path + ": cannot open"; return false; }
  std::string line;
  const std::string header = "ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow";
  if (!std::getline(in, line) || line.substr(0, header.size()) != header) {
    err = path + ":1: expected header '" + header + "'";
    return false;
  }
  size_t lineNo = 1;
  while ((limit == 0 || out.size() < limit) && std::getline(in, line)) {
    ++lineNo;
    if (line.empty() || line == "\r") continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    auto where = path + ":" + std::to_string(lineNo) + ": ";
    if (f.size() != 10) { err = where + std::to_string(f.size()) + " fields, expected 10 in '" + line + "'"; return false; }
    char* end;
    unsigned long n = std::strtoul(f[0].c_str(), &end, 10);
    if (*end || n != out.size()) { err = where + "ray number '" + f[0] + "', expected " + std::to_string(out.size()); return false; }
    float v[8];
    for (int k = 0; k < 8; ++k) {
      errno = 0;
      v[k] = std::strtof(f[k + 1].c_str(), &end);  // ERANGE (subnormals) still rounds correctly
      if (end == f[k + 1].c_str() || *end) { err = where + "'" + f[k + 1] + "' is not a float"; return false; }
    }
    if (f[9] != "0" && f[9] != "1") { err = where + "shadow flag '" + f[9] + "' (0 or 1)"; return false; }
    rtaccel_ray r{};
    r.ox = v[0]; r.oy = v[1]; r.oz = v[2]; r.dx = v[3]; r.dy = v[4]; r.dz = v[5]; r.tmin = v[6]; r.tmax = v[7];
    r.flags = f[9] == "1" ? 1u : 0u;
    out.push_back(r);
  }
  return true;
}

}  // namespace rtaccel::sim
