// An AXI4 slave (512- or 1024-bit data, 32-bit address) in front of the DDR
// channel model: what the ZC706's MIG (behind the AXI SmartConnect, which
// converts a 1024-bit port to the MIG's 512 bits) looks like to
// rtaccel_system's m_axi port. The DDR is charged the same either way: whole
// 64-byte bursts of every beat on one 12.8 GB/s channel.
//
// It is the C++ twin of the chiseltest harness's slave, sysmem's
// rtaccel.sim.axi.AxiMemoryModel (src/test/scala/rtaccel/axi/), call for call,
// random draw for random draw, so the two harnesses see the same cycles:
//  - timing: every burst (read or write) is a transfer on the DramModel
//    (latency drawn per burst; bytes charged in whole 64-byte bursts on one
//    channel of 12.8 GB/s shared by all); a read burst's beats are offered once
//    its transfer is done; a write is answered on B once its data is in and its
//    transfer is done (charged when its last beat pairs with its AW);
//  - back-pressure and order (seeded java.util.Random): arready, awready and
//    wready are each high with probability readyProb (arready/awready low at
//    maxReads/maxWrites); a ready R beat or B response is offered with
//    probability validProb; with `reorder`, a random ID's oldest done burst
//    goes next (in order within an ID); with `interleave`, R beats of
//    different IDs interleave (else a burst goes out whole, as the MIG);
//  - W beats are accepted before their AW (queued) and paired in order.
// Protocol: INCR bursts of full-width, aligned beats, len <= 255, no 4 KB
// crossing, wlast on exactly the last beat; AR/AW/W held stable while
// valid && !ready. A violation is recorded (violations()) and the burst is
// answered SLVERR (the chiseltest model throws instead).
//
// Cycle protocol (the harness calls, once per clock cycle):
//   1. drive(): this cycle's outputs, from state and the random draws only
//      (no combinational path from the master's valid to our ready);
//   2. commit(in): the master's signals, settled; handshakes happen here;
//   3. tick(): after the clock edge; the channel moves this cycle's data.
#pragma once
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "dram_model.hpp"
#include "java_random.hpp"
#include "sparse_memory.hpp"

namespace rtaccel::sim {

constexpr int kAxiMaxBeatBytes = 128;  // the widest m_axi data bus modelled: 1024 bits

struct AxiMemoryParams {
  double bytesPerCycle = 64.0;   // 12.8 GB/s at 200 MHz
  int burstBytes = 64;           // DDR3 x64 BL8
  int beatBytes = 64;            // m_axi data bytes: 64 (512-bit) or 128 (1024-bit); SystemSim sets the DUT's
  uint32_t latencyLo = 20;       // cycles (100 ns at 200 MHz)
  uint32_t latencyHi = 20;
  double readyProb = 1.0;
  double validProb = 1.0;
  bool reorder = true;
  bool interleave = false;
  uint32_t maxReads = 64;        // read bursts accepted and not fully sent
  uint32_t maxWrites = 64;       // write bursts accepted and not answered on B
  int64_t seed = 1;
};

// The master's signals (the DUT's outputs), sampled once they settled.
struct AxiMasterSignals {
  bool arvalid = false; uint32_t arid = 0; uint32_t araddr = 0; uint32_t arlen = 0, arsize = 0, arburst = 0;
  bool rready = false;
  bool awvalid = false; uint32_t awid = 0; uint32_t awaddr = 0; uint32_t awlen = 0, awsize = 0, awburst = 0;
  bool wvalid = false; const uint8_t* wdata = nullptr; uint64_t wstrb[kAxiMaxBeatBytes / 64] = {}; bool wlast = false;
  bool bready = false;
};

// The slave's signals for one cycle.
struct AxiSlaveSignals {
  bool arready = false, awready = false, wready = false;
  bool rvalid = false; uint32_t rid = 0; uint32_t rresp = 0; bool rlast = false;
  alignas(8) uint8_t rdata[kAxiMaxBeatBytes] = {};
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
  const DramModel& dram() const { return dram_; }
  const AxiMemoryStats& stats() const { return stats_; }
  // Protocol violations seen (the first few, each naming the cycle and the burst).
  const std::vector<std::string>& violations() const { return violations_; }
  int64_t now() const { return now_; }
  int beatBytes() const { return p_.beatBytes; }

  const AxiSlaveSignals& drive();
  void commit(const AxiMasterSignals& in);
  void tick();

  // Bytes of bursts per named address range (e.g. nodes, triangles, rays), since the last
  // batchStart(); a range of an existing name replaces it.
  void setRegion(const std::string& name, uint64_t lo, uint64_t hi);
  struct Region { std::string name; uint64_t lo, hi; int64_t readBytes = 0, writeBytes = 0; };
  const std::vector<Region>& regions() const { return regions_; }
  // Marks the start of a batch: sinceBatchStart() and the regions count from here.
  void batchStart();
  struct Snapshot { int64_t cycle = 0, dramBytes = 0, dramBusyCycles = 0; AxiMemoryStats axi; };
  Snapshot sinceBatchStart() const;

 private:
  struct Burst {
    uint64_t seq; uint32_t id; uint64_t addr; uint32_t beats;
    uint32_t resp;         // 0 OKAY, 2 SLVERR
    int handle = -1;       // DRAM transfer
    uint32_t done = 0;     // R beats sent, or W beats taken
  };
  struct WBeat { uint8_t data[kAxiMaxBeatBytes]; uint64_t strb[kAxiMaxBeatBytes / 64]; bool last; };
  struct Held { bool valid = false; uint32_t id, addr, len, size, burst; };
  uint32_t drawLatency();
  bool moved(const Burst& b) const { return b.handle >= 0 && dram_.done(b.handle); }
  uint32_t checkAddr(const char* ch, uint32_t id, uint32_t addr, uint32_t len, uint32_t size, uint32_t burst);
  void checkHeld(const char* ch, Held& held, bool valid, uint32_t id, uint32_t addr, uint32_t len, uint32_t size,
                 uint32_t burst, bool ready);
  int pick(const std::vector<Burst>& v, bool readSide);
  void charge(uint64_t addr, uint64_t bytes, bool write);
  void violation(const std::string& what);

  AxiMemoryParams p_;
  SparseMemory mem_;
  DramModel dram_;
  JavaRandom rnd_;
  int64_t now_ = 0;
  uint64_t seq_ = 0;
  std::vector<Burst> reads_;   // accepted, not fully sent; acceptance order
  std::deque<Burst> awWait_;   // write addresses waiting for their data
  std::deque<WBeat> wEarly_;   // W beats before their AW
  std::vector<Burst> writes_;  // data in, waiting for the DRAM or for B
  int64_t offerR_ = -1, offerB_ = -1;  // seq of the burst on offer (held until taken)
  std::vector<int> eligible_;  // scratch, reused (no allocation per cycle once warm)
  AxiSlaveSignals out_;
  Held heldAr_, heldAw_;
  AxiMemoryStats stats_;
  std::vector<std::string> violations_;
  int64_t violationCount_ = 0;
  std::vector<Region> regions_;
  Snapshot batch_;
};

}  // namespace rtaccel::sim
