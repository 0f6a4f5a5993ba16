#include "system_sim.hpp"

#include <cstring>
#include <utility>

#include "Vrtaccel_system.h"
#include "verilated.h"
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif

namespace rtaccel::sim {

namespace {
// The m_axi data width of the Verilated design (SystemConfig.axiDataBits): the byte size of its rdata port.
constexpr int kDutBeatBytes = int(sizeof(std::declval<Vrtaccel_system&>().m_axi_rdata));
static_assert(kDutBeatBytes == 64 || kDutBeatBytes == 128, "rtaccel_system's m_axi is neither 512 nor 1024 bits wide");
static_assert(sizeof(std::declval<Vrtaccel_system&>().m_axi_wstrb) == kDutBeatBytes / 8, "m_axi_wstrb: one bit per byte");
AxiMemoryParams withDutBeat(AxiMemoryParams p) {
  p.beatBytes = kDutBeatBytes;
  return p;
}
}  // namespace

int dutAxiDataBits() { return 8 * kDutBeatBytes; }

SystemSim::SystemSim(const AxiMemoryParams& mem, const char* vcdPath)
    : ctx_(new VerilatedContext), mem_(withDutBeat(mem)) {
  ctx_->randReset(0);  // registers without a reset start at 0 (with --x-initial fast as well)
  top_.reset(new Vrtaccel_system(ctx_.get(), "rtaccel_system"));
#if VM_TRACE
  if (vcdPath) {
    ctx_->traceEverOn(true);
    vcd_ = new VerilatedVcdC;
    top_->trace(vcd_, 99);
    vcd_->open(vcdPath);
  }
#else
  if (vcdPath) throw SimError(std::string("waveform ") + vcdPath + ": the simulator was built without --trace");
#endif
  top_->aclk = 0;
  top_->aresetn = 0;
  top_->eval();
}

SystemSim::~SystemSim() {
#if VM_TRACE
  if (vcd_) { vcd_->close(); delete vcd_; }
#endif
  top_->final();
}

void SystemSim::eval() {
  top_->eval();
#if VM_TRACE
  if (vcd_) vcd_->dump(2 * cycles_ + top_->aclk);
#endif
}

void SystemSim::reset(int cycles) {
  top_->aresetn = 0;
  for (int i = 0; i < cycles; ++i) step();
  top_->aresetn = 1;
}

// Verilator escapes the port name `interrupt` (a reserved word of some C compilers) as __SYM__interrupt.
bool SystemSim::interrupt() const { return top_->__SYM__interrupt; }

void SystemSim::step() {
  Vrtaccel_system& t = *top_;
  // 1. Outputs of the memory and of the register master, from state.
  const AxiSlaveSignals& m = mem_.drive();
  t.m_axi_arready = m.arready;
  t.m_axi_awready = m.awready;
  t.m_axi_wready = m.wready;
  t.m_axi_rvalid = m.rvalid;
  t.m_axi_rid = m.rid;
  t.m_axi_rresp = m.rresp;
  t.m_axi_rlast = m.rlast;
  std::memcpy(&t.m_axi_rdata[0], m.rdata, kDutBeatBytes);
  t.m_axi_bvalid = m.bvalid;
  t.m_axi_bid = m.bid;
  t.m_axi_bresp = m.bresp;
  t.s_axi_arvalid = arPending_;
  t.s_axi_araddr = liteAddr_;
  t.s_axi_arprot = 0;
  t.s_axi_rready = 1;
  t.s_axi_awvalid = awPending_;
  t.s_axi_awaddr = liteAddr_;
  t.s_axi_awprot = 0;
  t.s_axi_wvalid = wPending_;
  t.s_axi_wdata = liteData_;
  t.s_axi_wstrb = 0xf;
  t.s_axi_bready = 1;
  // 2. Settle the design's combinational outputs with the clock low.
  t.aclk = 0;
  eval();
  // 3. Handshakes on the settled signals.
  in_.arvalid = t.m_axi_arvalid; in_.arid = t.m_axi_arid; in_.araddr = t.m_axi_araddr;
  in_.arlen = t.m_axi_arlen; in_.arsize = t.m_axi_arsize; in_.arburst = t.m_axi_arburst;
  in_.rready = t.m_axi_rready;
  in_.awvalid = t.m_axi_awvalid; in_.awid = t.m_axi_awid; in_.awaddr = t.m_axi_awaddr;
  in_.awlen = t.m_axi_awlen; in_.awsize = t.m_axi_awsize; in_.awburst = t.m_axi_awburst;
  in_.wvalid = t.m_axi_wvalid; in_.wdata = reinterpret_cast<const uint8_t*>(&t.m_axi_wdata[0]);
  std::memcpy(in_.wstrb, &t.m_axi_wstrb, kDutBeatBytes / 8);  // a QData (512-bit bus) or a VlWide's words, little-endian
  in_.wlast = t.m_axi_wlast;
  in_.bready = t.m_axi_bready;
  if (t.aresetn) mem_.commit(in_);
  if (arPending_ && t.s_axi_arready) arPending_ = false;
  if (!arPending_ && !rDone_ && t.s_axi_rvalid) { rDone_ = true; rData_ = t.s_axi_rdata; liteResp_ = t.s_axi_rresp; }
  if (awPending_ && t.s_axi_awready) awPending_ = false;
  if (wPending_ && t.s_axi_wready) wPending_ = false;
  if (!awPending_ && !wPending_ && !bDone_ && t.s_axi_bvalid) { bDone_ = true; liteResp_ = t.s_axi_bresp; }
  // 4. The clock edge.
  t.aclk = 1;
  eval();
  mem_.tick();
  cycles_++;
}

void SystemSim::awaitLite(bool& done, const char* access, const char* respName, uint32_t offset) {
  for (int i = 0; i < kLiteTimeout && !done; ++i) step();
  if (!done) throw SimError(std::string("s_axi ") + access + " of register offset " + std::to_string(offset) +
                            ": no response in " + std::to_string(kLiteTimeout) + " cycles");
  done = false;
  if (liteResp_ != 0) throw SimError(std::string("s_axi ") + access + " of offset " + std::to_string(offset) + ": " +
                                     respName + " " + std::to_string(liteResp_));
}

uint32_t SystemSim::readReg(uint32_t offset) {
  liteAddr_ = offset;
  arPending_ = true;
  rDone_ = false;
  awaitLite(rDone_, "read", "RRESP", offset);
  return rData_;
}

void SystemSim::writeReg(uint32_t offset, uint32_t value) {
  liteAddr_ = offset;
  liteData_ = value;
  awPending_ = wPending_ = true;
  bDone_ = false;
  awaitLite(bDone_, "write", "BRESP", offset);
}

bool SystemSim::runUntilInterrupt(uint64_t maxCycles) {
  uint64_t start = cycles_;
  while (!interrupt()) {
    if (maxCycles && cycles_ - start >= maxCycles) return false;
    step();
  }
  return true;
}

}  // namespace rtaccel::sim
