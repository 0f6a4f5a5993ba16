#include "package_io.h"

#include <charconv>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rtg {

Image read_image(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Image img;
  std::string err;
  if (!parse_image(bytes.data(), bytes.size(), img, err)) throw std::runtime_error(path + ": " + err);
  return img;
}

std::vector<RayIn> read_rays_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::string line;
  std::getline(f, line);
  if (line.rfind("ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow", 0) != 0)
    throw std::runtime_error(path + ":1: not a rays.csv header: '" + line + "'");
  std::vector<RayIn> rays;
  size_t lineno = 1;
  while (std::getline(f, line)) {
    ++lineno;
    if (line.empty()) continue;
    // ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow: eight floats after the ray number, then the flag.
    float v[8];
    const char* p = std::strchr(line.c_str(), ',');
    for (int k = 0; k < 8; ++k) {
      if (p == nullptr) throw std::runtime_error(path + ":" + std::to_string(lineno) + ": expected 10 columns in '" + line + "'");
      char* end = nullptr;
      v[k] = std::strtof(p + 1, &end);  // rounds the decimal once, to nearest: the file's f32 exactly
      if (end == p + 1 || *end != ',')
        throw std::runtime_error(path + ":" + std::to_string(lineno) + ": column " + std::to_string(k + 2) + " is not a float in '" + line + "'");
      p = end;
    }
    RayIn r;
    for (int i = 0; i < 3; ++i) { r.o[i] = v[i]; r.d[i] = v[3 + i]; }
    r.tmin = v[6];
    r.tmax = v[7];
    if (std::strcmp(p + 1, "0") != 0 && std::strcmp(p + 1, "1") != 0)
      throw std::runtime_error(path + ":" + std::to_string(lineno) + ": shadow column is not 0 or 1 in '" + line + "'");
    r.shadow = p[1] == '1';
    rays.push_back(r);
  }
  return rays;
}

std::string float_text(float x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (std::isnan(x)) return "NaN";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);  // shortest round-trip form
  return std::string(buf, r.ptr);
}

void write_hits_csv(const std::string& path, const std::vector<HitOut>& hits) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  f << "ray,hit,t,u,v,prim,error\n";
  for (size_t i = 0; i < hits.size(); ++i) {
    const HitOut& h = hits[i];
    if (h.hit) f << i << ",1," << float_text(h.t) << ',' << float_text(h.u) << ',' << float_text(h.v) << ',' << h.prim << ',' << h.errors << '\n';
    else f << i << ",0,inf,0,0,-1," << h.errors << '\n';
  }
}

}  // namespace rtg
