// rtaccel_system under Verilator, clocked by C++ alone: the AXI4 memory
// (AxiMemory: the DDR model) on m_axi, and an AXI4-Lite master on s_axi that
// performs one register access at a time, as a CPU's load or store does.
//
// Each cycle: the models drive their outputs from state (Moore), eval with
// the clock low settles the design's combinational outputs, handshakes are
// decided on the settled signals, then eval with the clock high is the edge.
// Two evals per cycle is the least that is correct with paths from a port's
// valid to its ready inside the design.
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "axi_memory.hpp"

class Vrtaccel_system;
class VerilatedContext;
class VerilatedVcdC;

namespace rtaccel::sim {

// m_axi's data width in bits of the Verilated rtaccel_system linked in (SystemConfig.axiDataBits).
int dutAxiDataBits();

struct SimError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class SystemSim {
 public:
  explicit SystemSim(const AxiMemoryParams& mem, const char* vcdPath = nullptr);
  ~SystemSim();

  void reset(int cycles = 16);
  void step();
  // Register access through s_axi; throws SimError naming the register on a non-OKAY
  // response or no response within `kLiteTimeout` cycles.
  uint32_t readReg(uint32_t offset);
  void writeReg(uint32_t offset, uint32_t value);
  bool interrupt() const;
  uint64_t cycles() const { return cycles_; }
  AxiMemory& memory() { return mem_; }
  // Runs until `interrupt` is high; false if `maxCycles` (0: unbounded) passed first.
  bool runUntilInterrupt(uint64_t maxCycles);

  static constexpr int kLiteTimeout = 10000;

 private:
  void eval();
  // Steps until the s_axi handshake sets `done`, then checks the response code.
  void awaitLite(bool& done, const char* access, const char* respName, uint32_t offset);
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Vrtaccel_system> top_;
  [[maybe_unused]] VerilatedVcdC* vcd_ = nullptr;  // owned; complete type only with VM_TRACE (unused without)
  AxiMemory mem_;
  AxiMasterSignals in_;
  uint64_t cycles_ = 0;
  // AXI4-Lite master state: one access at a time.
  bool arPending_ = false, awPending_ = false, wPending_ = false;
  bool rDone_ = false, bDone_ = false;
  uint32_t liteAddr_ = 0, liteData_ = 0, rData_ = 0, liteResp_ = 0;
};

}  // namespace rtaccel::sim
