// The drop-in's `rtl` mode: rays through librtaccel's simulation backend (the
// Verilated rtaccel_system, sw/sim/), gathered from Nori's threads into
// batches. Built only when the drop-in links librtaccel's simulation
// (RTACCEL_SIM defined; nori-accel/Makefile's `rtl` target).
//
// How rays are gathered (docs/nori-dropin.md, "rtl mode"):
//   - trace() (any thread) appends the ray to a shared queue under a mutex,
//     wakes the submitter and waits on a condition variable until its ray
//     has an answer; the answer is copied into the caller's own request
//     (on its stack), so nothing is shared after the wake-up.
//   - One submitter thread owns the device (librtaccel allows one batch in
//     flight per device). It sleeps until a ray is queued, then gathers
//     more: the batch closes as soon as it holds one ray from every thread
//     that is asking (or `maxBatch` rays), or when `windowUs` has passed
//     since the first ray was queued. Rays that arrive while a batch runs
//     are queued and go in the next one. It submits the batch, waits for
//     DONE, reads the hits, and hands each waiting thread its hit (hit i is
//     ray i: the driver's numbering, checked).
//   - "Every thread that is asking": Nori's render threads each wait for
//     their own ray, so once each of them has one queued no more can come.
//     The batcher counts the threads whose rays it has seen since the last
//     window that ran out; a window that runs out forgets the threads that
//     did not show up in it (a render thread that finished its blocks), and
//     a thread is counted again at its next ray. So in a steady render a
//     batch holds one ray per render thread and closes without waiting; the
//     window is only spent when a thread leaves.
//   - A device failure (any status but OK) fails every ray of that batch and
//     every later one with the library's message: no ray is answered a miss
//     because the device broke.
// Latency: a ray waits at most `windowUs` for company, plus its batch's
// simulation. A batch holds at most as many rays as there are threads
// asking (each waits for its own ray), and at most `maxBatch`.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "../golden/walk.h"

struct rtaccel_dev;

namespace nori_rtl {

struct BatchOptions {
  uint32_t maxBatch = 256;  ///< rays per batch at most (RTACCEL_RTL_BATCH)
  /// How long a queued ray waits for company at most (RTACCEL_RTL_WINDOW_US).
  /// Spent only when a thread stops asking (a batch closes early once every
  /// asking thread has a ray in it), so it can be long against a render
  /// thread's shading time between two rays (microseconds) without slowing
  /// a steady render; 2 ms also rides out a render thread's being
  /// descheduled on a loaded machine.
  uint32_t windowUs = 2000;
};

struct BatchStats {
  uint64_t rays = 0, batches = 0, largestBatch = 0, simCycles = 0;
  std::map<uint32_t, uint64_t> sizes;  ///< batch size -> how many batches had it
  /// The median batch size (lower median; 0 before the first batch).
  uint32_t medianBatch() const;
  /// "1 x3, 2 x120": each batch size and how many batches had it.
  std::string histogram() const;
};

class RtlBatcher {
public:
    /// Opens the simulated system and loads `image` (image.bin bytes); throws naming the failure.
    RtlBatcher(const std::vector<uint8_t> &image, const BatchOptions &opt);
    ~RtlBatcher();
    RtlBatcher(const RtlBatcher &) = delete;
    RtlBatcher &operator=(const RtlBatcher &) = delete;

    /// The hardware's answer to one ray; blocks until its batch is done. Thread-safe.
    /// Throws std::runtime_error if the device failed.
    rtg::HitOut trace(const rtg::RayIn &ray);

    BatchStats stats();

private:
    struct Request;
    void submitLoop();
    void runBatch(std::vector<Request *> &batch);

    BatchOptions m_opt;
    rtaccel_dev *m_dev = nullptr;
    std::mutex m_lock;
    std::condition_variable m_queued;    ///< the submitter's wake-up
    std::condition_variable m_answered;  ///< the callers' wake-up
    std::deque<Request *> m_queue;
    std::set<std::thread::id> m_callers;  ///< threads seen asking since the last window ran out
    bool m_stop = false;
    std::string m_failure;  ///< set once the device failed; every later ray throws it
    BatchStats m_stats;
    std::thread m_submitter;
};

}  // namespace nori_rtl
