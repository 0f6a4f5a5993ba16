// An AXI4 slave (512-bit data, 32-bit address) in front of the DDR channel
// model: what the ZC706's MIG looks like to rtaccel_system's m_axi port.
//
// Protocol handled: INCR bursts of 1..256 beats of any size up to the bus
// width (a beat carries its whole 64-byte-aligned line; the master reads its
// lanes), FIXED and WRAP are refused (SLVERR, and a violation is recorded);
// bursts crossing a 4 KB boundary are recorded as violations (the contract
// forbids them); wstrb byte enables; IDs: reads return in order within an ID
// and out of order across IDs (whichever burst's data crossed the channel
// first), without interleaving beats of different bursts (as the MIG);
// B responses likewise in order within an ID. Beyond 4 GiB: DECERR.
//
// Cycle protocol (the harness calls, once per clock cycle):
//   1. drive(): the outputs for this cycle, from state only (no combinational
//      path from the master's valid to our ready: a Moore slave);
//   2. commit(in): the master's signals, settled; handshakes happen here;
//   3. tick(): after the clock edge; the channel moves this cycle's data.
// Timing as the Scala model: an AR accepted in cycle c with latency L offers
// its first beat from cycle c + L if the channel is free.
// Writes: the data is stored beat by beat as it arrives; the transfer is
// charged on the same channel when the last beat arrives (latency drawn then),
// and B is offered once its bytes have crossed.
// Latency: drawn per transfer (reads at AR, writes at the last W; in one
// cycle the read draws first) from one java.util.Random-compatible generator.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "dram_model.hpp"
#include "java_random.hpp"
#include "sparse_memory.hpp"

namespace rtaccel::sim {

constexpr int kAxiBeatBytes = 64;  // 512-bit data bus

struct AxiMemoryParams {
  double bytesPerCycle = 64.0;   // 12.8 GB/s at 200 MHz
  int burstBytes = 64;           // DDR3 x64 BL8
  uint32_t latencyLo = 20;       // cycles (100 ns at 200 MHz)
  uint32_t latencyHi = 20;
  uint32_t maxOutstanding = 64;  // read bursts accepted and not fully returned (and the same for writes)
  int64_t seed = 1;
};

// The master's signals (the DUT's outputs), sampled once they settled.
struct AxiMasterSignals {
  bool arvalid = false; uint32_t arid = 0; uint32_t araddr = 0; uint32_t arlen = 0, arsize = 0, arburst = 0;
  bool rready = false;
  bool awvalid = false; uint32_t awid = 0; uint32_t awaddr = 0; uint32_t awlen = 0, awsize = 0, awburst = 0;
  bool wvalid = false; const uint8_t* wdata = nullptr; uint64_t wstrb = 0; bool wlast = false;
  bool bready = false;
};

// The slave's signals for one cycle.
struct AxiSlaveSignals {
  bool arready = false, awready = false, wready = false;
  bool rvalid = false; uint32_t rid = 0; uint32_t rresp = 0; bool rlast = false;
  alignas(8) uint8_t rdata[kAxiBeatBytes] = {};
  bool bvalid = false; uint32_t bid = 0; uint32_t bresp = 0;
};

struct AxiMemoryStats {
  int64_t readBursts = 0, readBeats = 0, writeBursts = 0, writeBeats = 0;
  int64_t readStallCycles = 0;   // arvalid && !arready
  int64_t readOutstandingSum = 0;
  int64_t nonOkayResponses = 0;
};

class AxiMemory {
 public:
  explicit AxiMemory(const AxiMemoryParams& p);

  SparseMemory& memory() { return mem_; }
  const SparseMemory& memory() const { return mem_; }
  DramModel& dram() { return dram_; }
  const AxiMemoryStats& stats() const { return stats_; }
  // Protocol violations seen (each a sentence naming the cycle and the signal).
  const std::vector<std::string>& violations() const { return violations_; }
  int64_t now() const { return now_; }
  bool idle() const { return reads_.empty() && writes_.empty(); }

  const AxiSlaveSignals& drive();
  void commit(const AxiMasterSignals& in);
  void tick();

  // Bytes of bursts per named address range (e.g. nodes, triangles, rays), since the last
  // batchStart(); a range of an existing name replaces it.
  void setRegion(const std::string& name, uint64_t lo, uint64_t hi);
  struct Region { std::string name; uint64_t lo, hi; int64_t readBytes = 0, writeBytes = 0; };
  const std::vector<Region>& regions() const { return regions_; }
  // Marks the start of a batch: batchStats() and the regions count from here.
  void batchStart();
  struct Snapshot { int64_t cycle = 0, dramBytes = 0, dramBusyCycles = 0; AxiMemoryStats axi; };
  // What happened since batchStart() (everything, if never called).
  Snapshot sinceBatchStart() const;

 private:
  struct Burst {
    uint32_t id; uint64_t addr; uint32_t beats, size; uint64_t seq;
    uint32_t resp;        // 0 OKAY, 2 SLVERR, 3 DECERR
    int handle = -1;      // DRAM transfer (-1: not issued yet, writes only)
    uint32_t done = 0;    // beats sent (reads) or received (writes)
  };
  uint32_t drawLatency();
  uint32_t check(const char* ch, uint32_t id, uint64_t addr, uint32_t len, uint32_t size, uint32_t burst);
  uint64_t beatAddr(const Burst& b, uint32_t k) const;
  void charge(uint64_t addr, uint64_t bytes, bool write);
  int pickRead() const;
  int pickWrite() const;
  void violation(const std::string& what);

  AxiMemoryParams p_;
  SparseMemory mem_;
  DramModel dram_;
  JavaRandom rnd_;
  int64_t now_ = 0;
  uint64_t seq_ = 0;
  std::vector<Burst> reads_;   // accepted, not fully returned; issue order
  std::vector<Burst> writes_;  // accepted AWs until their B is taken; issue order
  int rOffer_ = -1, bOffer_ = -1;  // sticky offers: a valid stays up, unchanged, until taken
  AxiSlaveSignals out_;
  AxiMemoryStats stats_;
  std::vector<std::string> violations_;
  std::vector<Region> regions_;
  Snapshot batch_;
};

}  // namespace rtaccel::sim
