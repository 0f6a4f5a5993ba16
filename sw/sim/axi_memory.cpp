#include "axi_memory.hpp"

#include <algorithm>
#include <cstdio>

namespace rtaccel::sim {

namespace {
constexpr uint32_t kOkay = 0, kSlvErr = 2, kDecErr = 3;
constexpr uint32_t kIncr = 1;
constexpr size_t kMaxViolations = 32;  // the first few say what is wrong; the count says how often
}  // namespace

AxiMemory::AxiMemory(const AxiMemoryParams& p)
    : p_(p), dram_(p.bytesPerCycle, p.burstBytes), rnd_(p.seed) {
  reads_.reserve(p.maxOutstanding + 1);
  writes_.reserve(p.maxOutstanding + 1);
}

uint32_t AxiMemory::drawLatency() {
  if (p_.latencyLo == p_.latencyHi) return p_.latencyLo;
  return p_.latencyLo + uint32_t(rnd_.nextInt(int32_t(p_.latencyHi - p_.latencyLo + 1)));
}

void AxiMemory::violation(const std::string& what) {
  if (violations_.size() < kMaxViolations) violations_.push_back("cycle " + std::to_string(now_) + ": " + what);
}

void AxiMemory::setRegion(const std::string& name, uint64_t lo, uint64_t hi) {
  for (auto& r : regions_)
    if (r.name == name) { r.lo = lo; r.hi = hi; return; }
  regions_.push_back({name, lo, hi});
}

void AxiMemory::batchStart() {
  batch_ = Snapshot{now_, dram_.bytes(), dram_.busyCycles(), stats_};
  for (auto& r : regions_) r.readBytes = r.writeBytes = 0;
}

AxiMemory::Snapshot AxiMemory::sinceBatchStart() const {
  const AxiMemoryStats& a = stats_;
  const AxiMemoryStats& b = batch_.axi;
  Snapshot s{now_ - batch_.cycle, dram_.bytes() - batch_.dramBytes, dram_.busyCycles() - batch_.dramBusyCycles, {}};
  s.axi = {a.readBursts - b.readBursts, a.readBeats - b.readBeats, a.writeBursts - b.writeBursts,
           a.writeBeats - b.writeBeats, a.readStallCycles - b.readStallCycles,
           a.readOutstandingSum - b.readOutstandingSum, a.nonOkayResponses - b.nonOkayResponses};
  return s;
}

void AxiMemory::charge(uint64_t addr, uint64_t bytes, bool write) {
  for (auto& r : regions_) {
    uint64_t lo = std::max(addr, r.lo), hi = std::min(addr + bytes, r.hi);
    if (lo < hi) (write ? r.writeBytes : r.readBytes) += int64_t(hi - lo);
  }
}

uint32_t AxiMemory::check(const char* ch, uint32_t id, uint64_t addr, uint32_t len, uint32_t size, uint32_t burst) {
  char buf[200];
  uint64_t bytes = uint64_t(len + 1) << size;
  if (burst != kIncr || (1u << size) > kAxiBeatBytes) {
    std::snprintf(buf, sizeof buf, "%s id %u addr 0x%llx: burst type %u size %u (only INCR of <= 64-byte beats)", ch, id,
                  (unsigned long long)addr, burst, size);
    violation(buf);
    return kSlvErr;
  }
  if (addr + bytes > SparseMemory::kSpace) return kDecErr;
  if ((addr >> 12) != ((addr + bytes - 1) >> 12)) {
    std::snprintf(buf, sizeof buf, "%s id %u addr 0x%llx len %u: burst crosses a 4 KB boundary", ch, id,
                  (unsigned long long)addr, len);
    violation(buf);
  }
  return kOkay;
}

uint64_t AxiMemory::beatAddr(const Burst& b, uint32_t k) const {
  // INCR: the first beat at addr, later beats at the size-aligned address + k * size.
  if (k == 0) return b.addr;
  uint64_t step = 1ull << b.size;
  return (b.addr & ~(step - 1)) + uint64_t(k) * step;
}

// Eligible: the oldest read of its ID (in order within an ID) with a beat out
// of the channel; among them the one whose data became ready first.
int AxiMemory::pickRead() const {
  int best = -1;
  for (size_t i = 0; i < reads_.size(); ++i) {
    const Burst& b = reads_[i];
    bool oldest = true;
    for (size_t j = 0; j < i && oldest; ++j) oldest = reads_[j].id != b.id;
    if (!oldest || dram_.beatsMoved(b.handle) <= b.done) continue;
    if (best < 0 || dram_.readyAt(b.handle) < dram_.readyAt(reads_[best].handle)) best = int(i);
  }
  return best;
}

int AxiMemory::pickWrite() const {
  int best = -1;
  for (size_t i = 0; i < writes_.size(); ++i) {
    const Burst& b = writes_[i];
    bool oldest = true;
    for (size_t j = 0; j < i && oldest; ++j) oldest = writes_[j].id != b.id;
    if (!oldest || b.handle < 0 || !dram_.done(b.handle)) continue;
    if (best < 0 || dram_.readyAt(b.handle) < dram_.readyAt(writes_[best].handle)) best = int(i);
  }
  return best;
}

const AxiSlaveSignals& AxiMemory::drive() {
  out_.arready = reads_.size() < p_.maxOutstanding;
  out_.awready = writes_.size() < p_.maxOutstanding;
  // W data belongs to the oldest AW still short of beats (AXI4: no write interleaving).
  out_.wready = std::any_of(writes_.begin(), writes_.end(), [](const Burst& b) { return b.done < b.beats; });

  // R: keep offering the beat on offer (a burst once begun is finished before another starts).
  if (rOffer_ < 0 || dram_.beatsMoved(reads_[rOffer_].handle) <= reads_[rOffer_].done) {
    bool midBurst = rOffer_ >= 0 && reads_[rOffer_].done > 0;
    if (!midBurst) rOffer_ = pickRead();
  }
  out_.rvalid = rOffer_ >= 0 && dram_.beatsMoved(reads_[rOffer_].handle) > reads_[rOffer_].done;
  if (out_.rvalid) {
    const Burst& b = reads_[rOffer_];
    out_.rid = b.id;
    out_.rresp = b.resp;
    out_.rlast = b.done + 1 == b.beats;
    if (b.resp == kOkay) mem_.read(beatAddr(b, b.done) & ~uint64_t(kAxiBeatBytes - 1), out_.rdata, kAxiBeatBytes);
    else std::fill(std::begin(out_.rdata), std::end(out_.rdata), 0);
  }
  if (bOffer_ < 0) bOffer_ = pickWrite();
  out_.bvalid = bOffer_ >= 0;
  if (out_.bvalid) { out_.bid = writes_[bOffer_].id; out_.bresp = writes_[bOffer_].resp; }
  return out_;
}

void AxiMemory::commit(const AxiMasterSignals& in) {
  stats_.readOutstandingSum += int64_t(reads_.size());
  // Handshakes use this cycle's outputs (out_), computed by drive().
  if (in.arvalid && !out_.arready) stats_.readStallCycles++;
  if (in.arvalid && out_.arready) {
    Burst b{in.arid, in.araddr, in.arlen + 1, in.arsize, seq_++, 0};
    b.resp = check("AR", in.arid, in.araddr, in.arlen, in.arsize, in.arburst);
    uint64_t bytes = uint64_t(b.beats) << b.size;
    b.handle = dram_.issue(b.addr, uint32_t(bytes), 1u << b.size, drawLatency(), now_);
    charge(b.addr, bytes, false);
    reads_.push_back(b);
    stats_.readBursts++;
  }
  if (out_.rvalid && in.rready) {
    Burst& b = reads_[rOffer_];
    stats_.readBeats++;
    if (b.resp != kOkay) stats_.nonOkayResponses += b.done == 0;
    if (++b.done == b.beats) {
      dram_.release(b.handle);
      reads_.erase(reads_.begin() + rOffer_);
      rOffer_ = -1;
    }
  }
  if (in.awvalid && out_.awready) {
    Burst b{in.awid, in.awaddr, in.awlen + 1, in.awsize, seq_++, 0};
    b.resp = check("AW", in.awid, in.awaddr, in.awlen, in.awsize, in.awburst);
    writes_.push_back(b);
    stats_.writeBursts++;
  }
  if (in.wvalid && out_.wready) {
    auto it = std::find_if(writes_.begin(), writes_.end(), [](const Burst& b) { return b.done < b.beats; });
    Burst& b = *it;
    bool last = b.done + 1 == b.beats;
    if (in.wlast != last) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "W id %u beat %u of %u: wlast=%d", b.id, b.done + 1, b.beats, int(in.wlast));
      violation(buf);
    }
    if (b.resp == kOkay) mem_.writeLine(beatAddr(b, b.done) & ~uint64_t(kAxiBeatBytes - 1), in.wdata, in.wstrb);
    stats_.writeBeats++;
    if (++b.done == b.beats) {
      uint64_t bytes = uint64_t(b.beats) << b.size;
      b.handle = dram_.issue(b.addr, uint32_t(bytes), uint32_t(bytes), drawLatency(), now_);
      charge(b.addr, bytes, true);
    }
  }
  if (out_.bvalid && in.bready) {
    Burst& b = writes_[bOffer_];
    if (b.resp != kOkay) stats_.nonOkayResponses++;
    dram_.release(b.handle);
    writes_.erase(writes_.begin() + bOffer_);
    bOffer_ = -1;
  }
}

void AxiMemory::tick() {
  dram_.tick(now_);
  now_++;
}

}  // namespace rtaccel::sim
