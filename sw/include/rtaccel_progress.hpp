// A progress line for long runs of the project's C++ tools (rtaccel-sim,
// librtaccel's simulation backend, golden-trace). Not part of librtaccel's C
// API: a header-only helper, the C++ twin of rtaccel.regress.Progress (Scala).
//
// Rays answered of the total, percent, elapsed time and ETA, on stderr:
// - nothing for the first 3 s (short runs stay quiet);
// - stderr a terminal: one line redrawn in place with \r, at most 4 times a
//   second, ended with a newline by finish();
// - otherwise (CI logs, pipes): a plain line at most every 10 s, and a last
//   one from finish() if any was printed.
// RTACCEL_PROGRESS=off|plain|tty overrides the choice. Only what the user
// sees depends on time; nothing a test checks does (tests never read it).
#ifndef RTACCEL_PROGRESS_HPP
#define RTACCEL_PROGRESS_HPP

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>

namespace rtaccel {

class Progress {
 public:
  enum class Mode { Off, Plain, Tty };

  Progress(std::string label, uint64_t total, Mode mode = modeFor(stderr))
      : label_(std::move(label)), total_(total), mode_(mode), start_(Clock::now()) {}
  ~Progress() { finish(lastDone_); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Any thread; cheap when nothing is due (a clock read and, when due, a try-lock).
  void update(uint64_t done) {
    if (mode_ == Mode::Off || finished_.load(std::memory_order_relaxed)) return;
    const double s = seconds();
    if (s < kQuietSeconds || s < nextAt_.load(std::memory_order_relaxed)) return;
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_ || s < nextAt_) return;
    lastDone_ = done;
    draw(done, s);
    nextAt_ = s + (mode_ == Mode::Tty ? 0.25 : 10.0);
  }

  // The last line (if any was drawn); later updates print nothing.
  void finish(uint64_t done) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    finished_ = true;
    if (!drawn_) return;
    draw(done, seconds());
    if (mode_ == Mode::Tty) std::fputc('\n', stderr);
  }

  // "label [#####-----]  45.1%  29,538/65,536 rays  0:12 elapsed, ETA 0:15" (no bar in plain mode).
  static std::string line(const std::string& label, uint64_t done, uint64_t total, double seconds, bool bar) {
    const double frac = total ? double(done > total ? total : done) / double(total) : 1.0;
    std::string s = label + " ";
    if (bar) {
      const int w = 24, full = int(frac * w);
      s += "[" + std::string(size_t(full), '#') + std::string(size_t(w - full), '-') + "] ";
    }
    char buf[160];
    std::snprintf(buf, sizeof buf, "%5.1f%%  %s/%s rays  %s elapsed, ETA %s", 100.0 * frac, grouped(done).c_str(),
                  grouped(total).c_str(), clock(seconds).c_str(),
                  done ? clock(seconds * double(total - (done > total ? total : done)) / double(done)).c_str() : "?");
    return s + buf;
  }

  static Mode modeFor(FILE* f) {
    const char* e = std::getenv("RTACCEL_PROGRESS");
    if (e && !std::strcmp(e, "off")) return Mode::Off;
    if (e && !std::strcmp(e, "plain")) return Mode::Plain;
    if (e && !std::strcmp(e, "tty")) return Mode::Tty;
    return isatty(fileno(f)) ? Mode::Tty : Mode::Plain;
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr double kQuietSeconds = 3.0;

  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  void draw(uint64_t done, double s) {
    const std::string l = line(label_, done, total_, s, mode_ == Mode::Tty);
    // \r and a pad to clear a longer previous line; \x1b[K would be shorter but not every log viewer strips it.
    if (mode_ == Mode::Tty) std::fprintf(stderr, "\r%-*s", int(width_ > l.size() ? width_ : l.size()), l.c_str());
    else std::fprintf(stderr, "%s\n", l.c_str());
    std::fflush(stderr);
    width_ = l.size();
    drawn_ = true;
  }

  static std::string grouped(uint64_t n) {
    std::string d = std::to_string(n), s;
    for (size_t i = 0; i < d.size(); ++i) {
      if (i && (d.size() - i) % 3 == 0) s += ',';
      s += d[i];
    }
    return s;
  }
  static std::string clock(double s) {
    const long t = long(s + 0.5);
    char buf[32];
    if (t >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
    else std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
    return buf;
  }

  const std::string label_;
  const uint64_t total_;
  const Mode mode_;
  const Clock::time_point start_;
  std::mutex mutex_;
  std::atomic<double> nextAt_{0};  // read without the lock: a stale value only delays or repeats a check
  uint64_t lastDone_ = 0;
  size_t width_ = 0;
  bool drawn_ = false;
  std::atomic<bool> finished_{false};
};

}  // namespace rtaccel

#endif
