#include "axi_memory.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace rtaccel::sim {

namespace {
constexpr uint32_t kOkay = 0, kSlvErr = 2;
constexpr uint32_t kIncr = 1;
constexpr size_t kMaxViolations = 32;         // the first few say what is wrong; the count says how often
}  // namespace

AxiMemory::AxiMemory(const AxiMemoryParams& p) : p_(p), dram_(p.bytesPerCycle, p.burstBytes), rnd_(p.seed) {
  if (p.beatBytes != 64 && p.beatBytes != 128)
    throw std::invalid_argument("AxiMemory: beatBytes must be 64 or 128 (a 512- or 1024-bit bus), got " +
                                std::to_string(p.beatBytes));
  reads_.reserve(p.maxReads + 1);
  writes_.reserve(p.maxWrites + 1);
  eligible_.reserve(p.maxReads + p.maxWrites + 2);
}

uint32_t AxiMemory::drawLatency() {
  if (p_.latencyLo == p_.latencyHi) return p_.latencyLo;
  return p_.latencyLo + uint32_t(rnd_.nextInt(int32_t(p_.latencyHi - p_.latencyLo + 1)));
}

void AxiMemory::violation(const std::string& what) {
  if (violations_.size() < kMaxViolations) violations_.push_back("cycle " + std::to_string(now_) + ": " + what);
  violationCount_++;
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

uint32_t AxiMemory::checkAddr(const char* ch, uint32_t id, uint32_t addr, uint32_t len, uint32_t size, uint32_t burst) {
  char buf[220];
  const char* why = nullptr;
  if (burst != kIncr) why = "burst type is not INCR";
  else if ((1u << size) != uint32_t(p_.beatBytes)) why = "beats are not full width";
  else if (len > 255) why = "len > 255";
  else if (addr % p_.beatBytes) why = "address not aligned to the beat";
  else if ((addr % 4096) + uint64_t(len + 1) * p_.beatBytes > 4096) why = "burst crosses a 4 KB boundary";
  if (!why) return kOkay;
  std::snprintf(buf, sizeof buf, "%s id %u addr 0x%x len %u size %u burst %u: %s", ch, id, addr, len, size, burst, why);
  violation(buf);
  return kSlvErr;
}

void AxiMemory::checkHeld(const char* ch, Held& held, bool valid, uint32_t id, uint32_t addr, uint32_t len,
                          uint32_t size, uint32_t burst, bool ready) {
  if (held.valid) {
    if (!valid) violation(std::string(ch) + " valid dropped before ready");
    else if (held.id != id || held.addr != addr || held.len != len || held.size != size || held.burst != burst)
      violation(std::string(ch) + " payload changed while valid && !ready");
  }
  held = Held{valid && !ready, id, addr, len, size, burst};
}

// The burst to offer next, as AxiMemoryModel.pickRead / pickWrite: heads of
// their IDs whose transfer is done, in acceptance order; one of them at random
// (reorder), else only the oldest of all; a read burst begun goes on alone
// unless interleaving. Returns an index into v, or -1.
int AxiMemory::pick(const std::vector<Burst>& v, bool readSide) {
  eligible_.clear();
  int streaming = -1;
  if (readSide)
    for (size_t i = 0; i < v.size() && streaming < 0; ++i)
      if (v[i].done > 0) streaming = int(i);
  if (readSide && !p_.interleave && streaming >= 0) {
    if (moved(v[streaming])) eligible_.push_back(streaming);
  } else {
    // Heads of their IDs in one pass: a bit per ID seen so far (AXI IDs here are < 256;
    // a wider one falls back to the scan of the bursts before it).
    uint64_t seen[4] = {0, 0, 0, 0};
    for (size_t i = 0; i < v.size(); ++i) {
      uint32_t id = v[i].id;
      bool head = true;
      if (id < 256) {
        uint64_t bit = 1ULL << (id & 63);
        head = !(seen[id >> 6] & bit);
        seen[id >> 6] |= bit;
      } else {
        for (size_t j = 0; j < i && head; ++j) head = v[j].id != id;
      }
      if (head && moved(v[i])) {
        eligible_.push_back(int(i));
        if (!p_.reorder) break;  // heads.take(1)
      }
    }
    if (!p_.reorder && !eligible_.empty() && eligible_[0] != 0) eligible_.clear();  // only if it is the oldest of all
  }
  if (eligible_.empty()) return -1;
  return eligible_[rnd_.nextInt(int32_t(eligible_.size()))];
}


const AxiSlaveSignals& AxiMemory::drive() {
  auto indexOf = [](const std::vector<Burst>& v, int64_t seq) {
    for (size_t i = 0; i < v.size(); ++i)
      if (int64_t(v[i].seq) == seq) return int(i);
    return -1;
  };
  // The same draws, in the same order, as AxiMemoryModel.slave.
  if (offerR_ < 0 && rnd_.nextDouble() < p_.validProb) {
    int i = pick(reads_, true);
    offerR_ = i < 0 ? -1 : int64_t(reads_[i].seq);
  }
  if (offerB_ < 0 && rnd_.nextDouble() < p_.validProb) {
    int i = pick(writes_, false);
    offerB_ = i < 0 ? -1 : int64_t(writes_[i].seq);
  }
  out_.rvalid = offerR_ >= 0;
  if (out_.rvalid) {
    const Burst& b = reads_[indexOf(reads_, offerR_)];
    out_.rid = b.id;
    out_.rresp = b.resp;
    out_.rlast = b.done + 1 == b.beats;
    mem_.read(b.addr + uint64_t(b.done) * p_.beatBytes, out_.rdata, p_.beatBytes);
  }
  out_.bvalid = offerB_ >= 0;
  if (out_.bvalid) {
    const Burst& b = writes_[indexOf(writes_, offerB_)];
    out_.bid = b.id;
    out_.bresp = b.resp;
  }
  out_.arready = reads_.size() < p_.maxReads && rnd_.nextDouble() < p_.readyProb;
  out_.awready = awWait_.size() + writes_.size() < p_.maxWrites && rnd_.nextDouble() < p_.readyProb;
  out_.wready = rnd_.nextDouble() < p_.readyProb;
  return out_;
}

void AxiMemory::faultOn(Burst& b, bool write) {
  if (fault_.count == 0 || fault_.write != write || b.addr < fault_.lo || b.addr >= fault_.hi) return;
  if (fault_.skip > 0) {
    fault_.skip--;
    return;
  }
  fault_.count--;
  if (fault_.lost) b.lost = true;
  else b.resp = fault_.resp;
}

void AxiMemory::commit(const AxiMasterSignals& in) {
  stats_.readOutstandingSum += int64_t(reads_.size());
  if (in.arvalid && !out_.arready) stats_.readStallCycles++;
  checkHeld("AR", heldAr_, in.arvalid, in.arid, in.araddr, in.arlen, in.arsize, in.arburst, out_.arready);
  checkHeld("AW", heldAw_, in.awvalid, in.awid, in.awaddr, in.awlen, in.awsize, in.awburst, out_.awready);
  if (in.arvalid && out_.arready) {
    Burst b{seq_++, in.arid, in.araddr, in.arlen + 1, checkAddr("AR", in.arid, in.araddr, in.arlen, in.arsize, in.arburst)};
    faultOn(b, false);
    uint64_t bytes = uint64_t(b.beats) * p_.beatBytes;
    if (!b.lost) {
      b.handle = dram_.issue(b.addr, uint32_t(bytes), drawLatency(), now_);
      charge(b.addr, bytes, false);
      reads_.push_back(b);
    }
    stats_.readBursts++;
  }
  if (in.awvalid && out_.awready) {
    awWait_.push_back(Burst{seq_++, in.awid, in.awaddr, in.awlen + 1,
                            checkAddr("AW", in.awid, in.awaddr, in.awlen, in.awsize, in.awburst)});
    faultOn(awWait_.back(), true);
    stats_.writeBursts++;
  }
  if (in.wvalid && out_.wready) {
    WBeat w;
    std::copy(in.wdata, in.wdata + p_.beatBytes, w.data);
    std::copy(in.wstrb, in.wstrb + p_.beatBytes / 64, w.strb);
    w.last = in.wlast;
    wEarly_.push_back(w);
    stats_.writeBeats++;
  }
  while (!awWait_.empty() && !wEarly_.empty()) {
    Burst& b = awWait_.front();
    const WBeat& w = wEarly_.front();
    if (b.resp == kOkay && !b.lost)
      for (int k = 0; k < p_.beatBytes / 64; ++k)  // the beat's 64-byte lines, each under its 64 strobes
        mem_.writeLine(b.addr + uint64_t(b.done) * p_.beatBytes + 64 * k, w.data + 64 * k, w.strb[k]);
    b.done++;
    bool last = b.done == b.beats;
    if (w.last != last) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "W id %u beat %u of %u: wlast=%d", b.id, b.done, b.beats, int(w.last));
      violation(buf);
    }
    wEarly_.pop_front();
    if (last && b.lost) {
      awWait_.pop_front();
    } else if (last) {
      uint64_t bytes = uint64_t(b.beats) * p_.beatBytes;
      b.handle = dram_.issue(b.addr, uint32_t(bytes), drawLatency(), now_);
      charge(b.addr, bytes, true);
      writes_.push_back(b);
      awWait_.pop_front();
    }
  }
  if (out_.rvalid && in.rready) {
    auto it = std::find_if(reads_.begin(), reads_.end(), [&](const Burst& b) { return int64_t(b.seq) == offerR_; });
    stats_.readBeats++;
    if (it->resp != kOkay && it->done == 0) stats_.nonOkayResponses++;
    if (++it->done == it->beats) {
      dram_.release(it->handle);
      reads_.erase(it);
    }
    offerR_ = -1;  // every beat is offered afresh (AxiMemoryModel: offerR = None)
  }
  if (out_.bvalid && in.bready) {
    auto it = std::find_if(writes_.begin(), writes_.end(), [&](const Burst& b) { return int64_t(b.seq) == offerB_; });
    if (it->resp != kOkay) stats_.nonOkayResponses++;
    dram_.release(it->handle);
    writes_.erase(it);
    offerB_ = -1;
  }
}

void AxiMemory::tick() {
  dram_.tick(now_);
  now_++;
}

}  // namespace rtaccel::sim
