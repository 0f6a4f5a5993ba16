// The rtl mode's batcher (rtl_batcher.h says how rays are gathered).
#include "rtl_batcher.h"

#include <chrono>
#include <stdexcept>

#include "rtaccel.h"

namespace nori_rtl {

struct RtlBatcher::Request {
    rtaccel_ray ray{};
    rtaccel_hit hit{};
    std::thread::id caller;
    bool done = false;
    std::string failure;  ///< non-empty: the device failed on this ray's batch
};

namespace {
std::string failed(rtaccel_dev *dev, const char *what, rtaccel_status s) {
    return std::string("RTACCEL_MODE=rtl: ") + what + ": " + rtaccel_status_name(s) + ": " + rtaccel_last_error(dev);
}
}  // namespace

RtlBatcher::RtlBatcher(const std::vector<uint8_t> &image, const BatchOptions &opt) : m_opt(opt) {
    if (m_opt.maxBatch == 0)
        throw std::runtime_error("RTACCEL_RTL_BATCH=0: a batch needs at least one ray");
    rtaccel_sim_options o{};  // the defaults: 200 MHz fabric, 12.8 GB/s DDR, 100 ns latency, seed 1
    // A hang fails the ray instead of blocking Nori forever: no batch of
    // maxBatch rays needs this many cycles (the 65,536-ray Cornell image takes
    // about 530k; a dragon ray a few thousand).
    o.max_cycles = 1000000000ull;
    rtaccel_status s = rtaccel_open_sim(&o, &m_dev);
    if (s != RTACCEL_OK)
        throw std::runtime_error(std::string("RTACCEL_MODE=rtl: opening librtaccel's simulation: ") + rtaccel_status_name(s) + ": " +
                                 rtaccel_open_error());
    s = rtaccel_load_scene(m_dev, image.data(), image.size());
    if (s != RTACCEL_OK) {
        const std::string msg = failed(m_dev, "loading the scene's image.bin", s) + " (scene error " +
                                rtaccel_scene_error_name(rtaccel_scene_error(m_dev)) + ")";
        rtaccel_close(m_dev);
        throw std::runtime_error(msg);
    }
    m_submitter = std::thread([this] { submitLoop(); });
}

RtlBatcher::~RtlBatcher() {
    {
        std::lock_guard<std::mutex> g(m_lock);
        m_stop = true;
    }
    m_queued.notify_all();
    m_submitter.join();
    rtaccel_close(m_dev);
}

rtg::HitOut RtlBatcher::trace(const rtg::RayIn &r) {
    Request q;
    q.caller = std::this_thread::get_id();
    q.ray = {r.o[0], r.o[1], r.o[2], r.d[0], r.d[1], r.d[2], r.tmin, r.tmax, r.shadow ? 1u : 0u, {0, 0, 0}};
    {
        std::unique_lock<std::mutex> g(m_lock);
        if (!m_failure.empty())
            throw std::runtime_error(m_failure);
        m_queue.push_back(&q);
        m_callers.insert(q.caller);
        m_queued.notify_one();
        m_answered.wait(g, [&] { return q.done; });
    }
    if (!q.failure.empty())
        throw std::runtime_error(q.failure);
    rtg::HitOut h;
    h.hit = (q.hit.status & RTACCEL_HIT_FLAG) != 0;
    h.t = q.hit.t;
    h.u = q.hit.u;
    h.v = q.hit.v;
    h.prim = h.hit ? static_cast<int64_t>(q.hit.prim) : -1;
    h.errors = RTACCEL_HIT_ERRORS(q.hit.status);
    return h;
}

uint32_t BatchStats::medianBatch() const {
    uint64_t seen = 0;
    for (const auto &[size, count] : sizes)
        if ((seen += count) * 2 >= batches)
            return size;
    return 0;
}

std::string BatchStats::histogram() const {
    std::string s;
    for (const auto &[size, count] : sizes)
        s += (s.empty() ? "" : ", ") + std::to_string(size) + " x" + std::to_string(count);
    return s;
}

BatchStats RtlBatcher::stats() {
    std::lock_guard<std::mutex> g(m_lock);
    return m_stats;
}

void RtlBatcher::submitLoop() {
    std::vector<Request *> batch;
    for (;;) {
        {
            std::unique_lock<std::mutex> g(m_lock);
            m_queued.wait(g, [&] { return m_stop || !m_queue.empty(); });
            if (m_queue.empty())
                return;  // stopping, and no caller waits (each caller holds its request until answered)
            // Full: one ray from every asking thread, or maxBatch. Each asking
            // thread has at most one ray queued (it waits for it), so the
            // queue reaching the number of asking threads means all are in.
            auto full = [&] { return m_queue.size() >= std::min<size_t>(m_opt.maxBatch, m_callers.size()); };
            const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(m_opt.windowUs);
            const bool closedEarly = m_queued.wait_until(g, until, [&] { return m_stop || full(); });
            while (!m_queue.empty() && batch.size() < m_opt.maxBatch) {
                batch.push_back(m_queue.front());
                m_queue.pop_front();
            }
            if (!closedEarly) {  // the window ran out: forget the threads that did not ask in it
                m_callers.clear();
                for (const Request *q : batch)
                    m_callers.insert(q->caller);
                for (const Request *q : m_queue)
                    m_callers.insert(q->caller);
            }
        }
        runBatch(batch);  // the device is this thread's alone: no lock held while it simulates
        {
            std::lock_guard<std::mutex> g(m_lock);
            for (Request *q : batch)
                q->done = true;
            batch.clear();
        }
        m_answered.notify_all();
    }
}

void RtlBatcher::runBatch(std::vector<Request *> &batch) {
    std::string failure;
    {
        std::lock_guard<std::mutex> g(m_lock);
        failure = m_failure;
    }
    if (failure.empty()) {
        std::vector<rtaccel_ray> rays(batch.size());
        std::vector<rtaccel_hit> hits(batch.size());
        for (size_t i = 0; i < batch.size(); ++i)
            rays[i] = batch[i]->ray;
        const auto n = static_cast<uint32_t>(batch.size());
        rtaccel_status s = rtaccel_submit(m_dev, rays.data(), n);
        if (s != RTACCEL_OK) failure = failed(m_dev, "rtaccel_submit", s);
        if (failure.empty() && (s = rtaccel_wait(m_dev, 0)) != RTACCEL_OK) failure = failed(m_dev, "rtaccel_wait", s);
        if (failure.empty() && (s = rtaccel_read_hits(m_dev, hits.data(), n)) != RTACCEL_OK)
            failure = failed(m_dev, "rtaccel_read_hits", s);
        for (uint32_t i = 0; failure.empty() && i < n; ++i) {
            if (hits[i].number != i)
                failure = "RTACCEL_MODE=rtl: hit record " + std::to_string(i) + " of a batch of " + std::to_string(n) +
                          " carries ray number " + std::to_string(hits[i].number);
            else
                batch[i]->hit = hits[i];
        }
        uint64_t cycles = 0;
        rtaccel_sim_cycles(m_dev, &cycles);
        std::lock_guard<std::mutex> g(m_lock);
        m_stats.rays += n;
        m_stats.batches += 1;
        m_stats.largestBatch = std::max<uint64_t>(m_stats.largestBatch, n);
        m_stats.sizes[n] += 1;
        m_stats.simCycles = cycles;
        if (!failure.empty())
            m_failure = failure;
    }
    for (Request *q : batch)
        q->failure = failure;
}

}  // namespace nori_rtl
