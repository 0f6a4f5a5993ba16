// The DDR channel the Scala DramModel (src/main/scala/rtaccel/sim/mem/DramModel.scala)
// charges, for AXI bursts: each transfer waits its latency, then its bytes,
// charged as whole DRAM bursts, cross one channel of `bytesPerCycle` shared by
// every transfer (reads and writes alike).
//
// Timing, as in DramModel: a transfer issued in cycle c with latency L that
// fits one cycle of channel completes in the tick of cycle c + L - 1 if the
// channel is free, so its requester sees it from cycle c + L on; each further
// cycle of channel it needs, or spends waiting for another transfer, adds one.
// Arbitration: the transfer that became ready first (ties: issued first).
// Bandwidth is kept in thousandths of a byte, so a clock that does not divide
// the peak (51.2 B/cycle at 250 MHz) accumulates no rounding.
// For AXI a transfer is one burst (AxiMemory).
#pragma once
#include <cstdint>
#include <vector>

namespace rtaccel::sim {

class DramModel {
 public:
  DramModel(double bytesPerCycle, int burstBytes);

  // Bytes a DRAM moves for `n` bytes at `addr`: every burst-aligned burst the range touches.
  static int64_t burstCharge(uint64_t addr, uint64_t n, int burst);

  // Starts a transfer of `bytes` at `addr`; returns a handle valid until it is released.
  int issue(uint64_t addr, uint32_t bytes, uint32_t latency, int64_t now);
  // Moves cycle `now`'s data (once per cycle, cycles consecutive).
  void tick(int64_t now);
  bool done(int h) const { return slots_[h].milliLeft == 0; }
  // Cycle the transfer became (or becomes) eligible for the channel.
  int64_t readyAt(int h) const { return slots_[h].readyAt; }
  void release(int h);

  int64_t bytes() const { return bytes_; }
  int64_t busyCycles() const { return busyCycles_; }
  double bytesPerCycle() const { return bytesPerCycle_; }
  int burstBytes() const { return burstBytes_; }

 private:
  struct Slot {
    bool used = false;
    uint64_t seq = 0;
    int64_t readyAt = 0;
    int64_t milliLeft = 0;
  };
  double bytesPerCycle_;
  int burstBytes_;
  int64_t milliPerCycle_;
  std::vector<Slot> slots_;   // reused: no allocation per cycle once warm
  std::vector<int> free_;
  std::vector<int> pending_;  // handles with bytes left, in issue order
  uint64_t nextSeq_ = 0;
  int64_t lastTick_ = -1;
  int64_t bytes_ = 0, busyCycles_ = 0;
};

}  // namespace rtaccel::sim
