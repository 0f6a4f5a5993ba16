#include "dram_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rtaccel::sim {

DramModel::DramModel(double bytesPerCycle, int burstBytes)
    : bytesPerCycle_(bytesPerCycle), burstBytes_(burstBytes), milliPerCycle_(std::llround(bytesPerCycle * 1000)) {
  if (!(bytesPerCycle > 0)) throw std::invalid_argument("DramModel: bytesPerCycle must be > 0");
  if (burstBytes < 1) throw std::invalid_argument("DramModel: burstBytes must be >= 1");
  slots_.reserve(1024);
  free_.reserve(1024);
  pending_.reserve(1024);
}

int64_t DramModel::burstCharge(uint64_t addr, uint64_t n, int burst) {
  if (n < 1) throw std::invalid_argument("burstCharge: need n >= 1");
  return int64_t((addr + n - 1) / burst - addr / burst + 1) * burst;
}

int DramModel::issue(uint64_t addr, uint32_t bytes, uint32_t latency, int64_t now) {
  if (latency < 1) throw std::invalid_argument("DramModel: latency must be >= 1 cycle");
  if (now <= lastTick_)
    throw std::logic_error("DramModel: issue in cycle " + std::to_string(now) + " after the channel moved cycle " +
                           std::to_string(lastTick_) + "'s data");
  int h;
  if (!free_.empty()) {
    h = free_.back();
    free_.pop_back();
  } else {
    h = int(slots_.size());
    slots_.emplace_back();
  }
  Slot& s = slots_[h];
  int64_t charged = burstCharge(addr, bytes, burstBytes_);
  s.used = true;
  s.seq = nextSeq_++;
  s.readyAt = now + latency - 1;
  s.milliLeft = charged * 1000;
  pending_.push_back(h);
  bytes_ += charged;
  return h;
}

void DramModel::tick(int64_t now) {
  if (now == lastTick_) return;
  if (now != lastTick_ + 1)
    throw std::logic_error("DramModel: ticked for cycle " + std::to_string(now) + " after cycle " + std::to_string(lastTick_));
  lastTick_ = now;
  int64_t budget = milliPerCycle_;
  bool moved = false;
  while (budget > 0) {
    // Next: ready by now, earliest readyAt, ties issued first (pending_ is in issue order).
    int bestAt = -1;
    for (size_t i = 0; i < pending_.size(); ++i) {
      const Slot& s = slots_[pending_[i]];
      if (s.readyAt <= now && (bestAt < 0 || s.readyAt < slots_[pending_[bestAt]].readyAt)) bestAt = int(i);
    }
    if (bestAt < 0) break;
    Slot& s = slots_[pending_[bestAt]];
    int64_t n = std::min(budget, s.milliLeft);
    s.milliLeft -= n;
    budget -= n;
    moved = true;
    if (s.milliLeft == 0) pending_.erase(pending_.begin() + bestAt);
  }
  if (moved) busyCycles_ += 1;
}

void DramModel::release(int h) {
  if (!slots_[h].used || slots_[h].milliLeft != 0) throw std::logic_error("DramModel: release of a transfer not done");
  slots_[h].used = false;
  free_.push_back(h);
}

}  // namespace rtaccel::sim
