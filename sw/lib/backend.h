/* The one interface the driver (rtaccel.c) needs of a backend: 32-bit register
 * access, a window of device memory, and waiting for the interrupt line.
 * Every function returns an rtaccel_status and, on failure, writes a sentence
 * into err (errn bytes). */
#ifndef RTACCEL_BACKEND_H
#define RTACCEL_BACKEND_H

#include "rtaccel.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rtaccel_backend {
  const char* name;
  rtaccel_status (*reg_read)(void* ctx, uint32_t offset, uint32_t* value, char* err, size_t errn);
  rtaccel_status (*reg_write)(void* ctx, uint32_t offset, uint32_t value, char* err, size_t errn);
  /* addr: device (bus) address inside [buf_base, buf_base + buf_size) */
  rtaccel_status (*mem_write)(void* ctx, uint64_t addr, const void* src, size_t n, char* err, size_t errn);
  rtaccel_status (*mem_read)(void* ctx, uint64_t addr, void* dst, size_t n, char* err, size_t errn);
  /* Returns RTACCEL_OK once the interrupt line is high (it may already be). */
  rtaccel_status (*wait_irq)(void* ctx, uint32_t timeout_ms, char* err, size_t errn);
  /* Optional (sim only; NULL elsewhere). */
  rtaccel_status (*sim_cycles)(void* ctx, uint64_t* cycles);
  rtaccel_status (*sim_memory_json)(void* ctx, const char* path, char* err, size_t errn);
  /* Names an address range for the memory statistics (replaces a range of the same name). */
  void (*sim_region)(void* ctx, const char* name, uint64_t lo, uint64_t hi);
  /* A batch starts now: the memory statistics of the batch count from here. */
  void (*sim_batch_start)(void* ctx);
  void (*close)(void* ctx);
  /* Optional (sim only): CONFIG_AXI_DATA_BITS of the simulated system, known without an s_axi access. */
  uint32_t (*sim_axi_data_bits)(void* ctx);
  /* Optional (sim only): run the system `cycles` cycles. */
  rtaccel_status (*sim_run)(void* ctx, uint64_t cycles, char* err, size_t errn);
} rtaccel_backend;

/* Called by a backend's open function once it holds its context; takes ownership. */
rtaccel_status rtaccel_attach(const rtaccel_backend* be, void* ctx, uint64_t buf_base, uint64_t buf_size,
                              rtaccel_dev** out);
/* The backend context of a device opened with `be` (NULL for another backend's): the sim's fault harness. */
void* rtaccel_backend_context(rtaccel_dev* dev, const rtaccel_backend* be);
/* Records an open failure for rtaccel_open_error (thread-local). */
void rtaccel_set_open_error(const char* fmt, ...);

#ifdef __cplusplus
}
#endif

#endif
