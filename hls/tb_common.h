// Shared test-bench plumbing: paths, seed, per-family counters, failures.
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "rng.h"

namespace rt {

// Documented default seed (docs/kernels.md); override with RT_SEED=<n>.
constexpr uint64_t kDefaultSeed = 0x5eed0004ull;

inline std::string env_or(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return (v && *v) ? v : fallback;
}
inline std::string testdata_dir() { return env_or("RT_TESTDATA", "../testdata/kernels"); }
inline std::string vectors_dir() { return env_or("RT_VECTORS", "build/vectors"); }
inline long random_count() { return std::strtol(env_or("RT_RANDOM", "100000").c_str(), nullptr, 10); }

// Counters per case family; printed as one table with a column per counter.
class Tally {
 public:
  void add(const std::string& family, const std::string& counter, long n = 1) {
    rows_[family][counter] += n;
    rows_["ALL"][counter] += n;
    if (std::find(cols_.begin(), cols_.end(), counter) == cols_.end()) cols_.push_back(counter);
  }
  long get(const std::string& family, const std::string& counter) const {
    auto r = rows_.find(family);
    if (r == rows_.end()) return 0;
    auto c = r->second.find(counter);
    return c == r->second.end() ? 0 : c->second;
  }
  void print(const char* title) const {
    std::printf("%s\n%-14s", title, "family");
    for (auto& c : cols_) std::printf(" %14s", c.c_str());
    std::printf("\n");
    for (auto& r : rows_) {
      std::printf("%-14s", r.first.c_str());
      for (auto& c : cols_) std::printf(" %14ld", get(r.first, c));
      std::printf("\n");
    }
  }

 private:
  std::map<std::string, std::map<std::string, long>> rows_;
  std::vector<std::string> cols_;
};

// Collects failed checks; prints the first few with the seed, exits non-zero.
class Failures {
 public:
  explicit Failures(uint64_t seed) : seed_(seed) {}
  void add(const std::string& what) {
    if (list_.size() < 20) list_.push_back(what);
    ++count_;
  }
  int finish(const char* bench) const {
    if (count_ == 0) {
      std::printf("%s: PASS (seed 0x%llx)\n", bench, static_cast<unsigned long long>(seed_));
      return 0;
    }
    for (auto& s : list_) std::printf("FAIL %s\n", s.c_str());
    std::printf("%s: %ld check(s) FAILED (seed 0x%llx; rerun with RT_SEED=0x%llx)\n", bench, count_,
                static_cast<unsigned long long>(seed_), static_cast<unsigned long long>(seed_));
    return 1;
  }

 private:
  uint64_t seed_;
  long count_ = 0;
  std::vector<std::string> list_;
};

}  // namespace rt
