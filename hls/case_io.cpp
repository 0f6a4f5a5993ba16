#include "case_io.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "fp32.h"

namespace rt {

namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

bool valid_family(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'))
      return false;
  return true;
}

float parse_hex(const std::string& tok, const std::string& path, int line) {
  if (tok.size() != 8) fail(path, line, "expected 8 hex digits, got '" + tok + "'");
  for (char c : tok)
    if (!std::isxdigit(static_cast<unsigned char>(c))) fail(path, line, "not a hex bit pattern: '" + tok + "'");
  return from_bits(static_cast<uint32_t>(std::stoul(tok, nullptr, 16)));
}

// Splits every non-comment line into tokens; checks the count and family.
template <typename Fill>
void read_lines(const std::string& path, size_t floats, Fill fill) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path + ": cannot open (it is committed in testdata/kernels/; "
                             "regenerate with `make -C hls hard-cases`)");
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    const size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::istringstream ss(text);
    std::vector<std::string> tok;
    for (std::string t; ss >> t;) tok.push_back(t);
    if (tok.empty()) continue;
    if (tok.size() != floats + 1)
      fail(path, line, "expected a family and " + std::to_string(floats) + " values, got " +
                           std::to_string(tok.size()) + " tokens");
    if (!valid_family(tok[0])) fail(path, line, "bad family name '" + tok[0] + "' (use [a-z0-9_])");
    std::vector<float> v;
    for (size_t i = 1; i < tok.size(); ++i) v.push_back(parse_hex(tok[i], path, line));
    fill(tok[0], v);
  }
}

}  // namespace

std::vector<BoxCase> read_box_cases(const std::string& path) {
  std::vector<BoxCase> out;
  read_lines(path, 14, [&](const std::string& fam, const std::vector<float>& v) {
    BoxCase c;
    c.family = fam;
    for (int i = 0; i < 3; ++i) {
      c.o[i] = v[i]; c.d[i] = v[3 + i]; c.bmin[i] = v[8 + i]; c.bmax[i] = v[11 + i];
    }
    c.tmin = v[6]; c.tmax = v[7];
    out.push_back(c);
  });
  return out;
}

std::vector<TriCase> read_tri_cases(const std::string& path) {
  std::vector<TriCase> out;
  read_lines(path, 17, [&](const std::string& fam, const std::vector<float>& v) {
    TriCase c;
    c.family = fam;
    for (int i = 0; i < 3; ++i) {
      c.o[i] = v[i]; c.d[i] = v[3 + i];
      c.p0[i] = v[8 + i]; c.p1[i] = v[11 + i]; c.p2[i] = v[14 + i];
    }
    c.tmin = v[6]; c.tmax = v[7];
    out.push_back(c);
  });
  return out;
}

std::string hex(float x) {
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", file_bits(x));
  return buf;
}

namespace {
void put3(std::string& s, const float v[3]) {
  for (int i = 0; i < 3; ++i) { s += ' '; s += hex(v[i]); }
}
}  // namespace

std::string box_inputs_line(const BoxCase& c) {
  std::string s = c.family;
  put3(s, c.o); put3(s, c.d);
  s += ' ' + hex(c.tmin) + ' ' + hex(c.tmax);
  put3(s, c.bmin); put3(s, c.bmax);
  return s;
}

std::string tri_inputs_line(const TriCase& c) {
  std::string s = c.family;
  put3(s, c.o); put3(s, c.d);
  s += ' ' + hex(c.tmin) + ' ' + hex(c.tmax);
  put3(s, c.p0); put3(s, c.p1); put3(s, c.p2);
  return s;
}

FILE* open_or_throw(const std::string& path, const char* mode) {
  FILE* f = std::fopen(path.c_str(), mode);
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  return f;
}

}  // namespace rt
