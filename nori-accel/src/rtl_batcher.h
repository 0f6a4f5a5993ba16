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
//     flight per device). It sleeps until a ray is queued, then waits up to
//     `windowUs` more for the queue to reach `maxBatch` rays (rays that
//     arrive while a batch runs are queued and go in the next one), takes up
//     to `maxBatch`, submits them, waits for DONE, reads the hits, and hands
//     each waiting thread its hit (hit i is ray i: the driver's numbering,
//     checked).
//   - A device failure (any status but OK) fails every ray of that batch and
//     every later one with the library's message: no ray is answered a miss
//     because the device broke.
// Latency: a ray waits at most `windowUs` for company, plus its batch's
// simulation. Nori's threads each wait for their own ray, so a batch holds
// at most as many rays as Nori has threads (plus any other callers).
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "../golden/walk.h"

struct rtaccel_dev;

namespace nori_rtl {

struct BatchOptions {
  uint32_t maxBatch = 256;  ///< rays per batch at most (RTACCEL_RTL_BATCH)
  uint32_t windowUs = 200;  ///< how long a queued ray waits for company (RTACCEL_RTL_WINDOW_US)
};

struct BatchStats {
  uint64_t rays = 0, batches = 0, largestBatch = 0, simCycles = 0;
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
    bool m_stop = false;
    std::string m_failure;  ///< set once the device failed; every later ray throws it
    BatchStats m_stats;
    std::thread m_submitter;
};

}  // namespace nori_rtl
